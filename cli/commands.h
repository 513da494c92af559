#pragma once
// One function per subcommand; argv[first] is the first argument after the
// subcommand name. Each returns the process exit code.
namespace seamap::cli {

int RunSimulate(int argc, char** argv, int first);       // cli/simulate_command.cc
int RunBuild(int argc, char** argv, int first);          // cli/build_command.cc
int RunInfo(int argc, char** argv, int first);           // cli/info_command.cc
int RunEnhance(int argc, char** argv, int first);        // cli/enhance_command.cc
int RunEnhanceReport(int argc, char** argv, int first);  // cli/enhance_command.cc
int RunServe(int argc, char** argv, int first);          // cli/serve_command.cc
int RunReplay(int argc, char** argv, int first);         // cli/replay_command.cc
int RunExport(int argc, char** argv, int first);         // cli/export_command.cc
int RunTrajectory(int argc, char** argv, int first);     // cli/trajectory_command.cc

int RunTrajectoryEval(int argc, char** argv, int first);  // cli/trajectory_eval_command.cc
int RunGeoref(int argc, char** argv, int first);          // cli/georef_command.cc
int RunSimulateBuoy(int argc, char** argv, int first);    // cli/simulate_buoy_command.cc
int RunGeorefEval(int argc, char** argv, int first);      // cli/georef_eval_command.cc
int RunMapEval(int argc, char** argv, int first);         // cli/map_eval_command.cc

int RunSimulateStereo(int argc, char** argv, int first);  // cli/stereo_simulate_command.cc
int RunStereoModel(int argc, char** argv, int first);     // cli/stereo_model_command.cc
int RunStereoLocate(int argc, char** argv, int first);    // cli/stereo_locate_command.cc
int RunStereoPoints(int argc, char** argv, int first);    // cli/stereo_points_command.cc

int RunDetect(int argc, char** argv, int first);          // cli/detect_command.cc
int RunDetectionsPack(int argc, char** argv, int first);  // cli/detections_pack_command.cc
int RunTrainingData(int argc, char** argv, int first);    // cli/training_data_command.cc
int RunReview(int argc, char** argv, int first);          // cli/review_command.cc

}  // namespace seamap::cli
