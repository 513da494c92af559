#pragma once
// Simulated objects on the seabed (tyres, crates, pipes, anchors, rocks),
// painted into the seabed texture before frames are rendered so that every
// frame and the map see them consistently. Their truth (truth/objects.csv,
// truth/objects.json) trains and evaluates the object detector.
#include <cstdint>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "core/geo/local_frame.h"
#include "core/sim/seabed_texture.h"

namespace seamap {

// Class names in id order (the shipped detector's class ids).
const std::vector<std::string>& SeabedObjectClasses();
// Every class the simulator paints, in id order: the shipped model's five,
// then the ones it does not know (drum: 0.6 m diameter, 0.9 m long, lying or
// standing, banded and rusty).
const std::vector<std::string>& SimulatedObjectClasses();
// Hard negatives (--clutter): look-alikes that are no labelled object, in
// kind order: a ring of small rocks (tyre-shaped), a short pipe piece, a dark
// rock. Their ids follow SimulatedObjectClasses' (see SeabedObject::negative()).
const std::vector<std::string>& ClutterKinds();
// Class ids of a comma-separated list of SimulatedObjectClasses names;
// InputError naming `option` for an unknown, repeated or missing name.
std::vector<int> ParseObjectClasses(const std::string& list, const std::string& option);

struct SeabedObject {
  int class_id = 0;
  double angle_rad = 0;                    // object axis u from east, counter-clockwise
  double length_m = 0;                     // along u (diameter for tyres and rocks)
  double width_m = 0;                      // along v
  double height_m = 0;                     // above the seabed, for shading and the shadow
  double ref_east_m = 0, ref_north_m = 0;  // where the object's own origin lies
  uint64_t shape_seed = 0;                 // irregular outlines (rocks), surface detail
  bool standing = false;                   // drum: on its end (a disc from above), else lying
  double buried_fraction = 0;              // of height_m under sediment (--bury); 0 paints as before
  // Derived by PlaceSeabedObjects: the footprint (convex, counter-clockwise,
  // east/north metres) and its east/north-aligned bounding box. The truth
  // centre is the box centre (what a box detector reports), not the centroid.
  std::vector<LocalXY> footprint_m;
  double centre_east_m = 0, centre_north_m = 0;
  double box_width_m = 0, box_height_m = 0;  // east-west, north-south
  double size_m() const { return std::max(box_width_m, box_height_m); }
  bool negative() const;                  // clutter: painted, never a label
  const std::string& class_name() const;  // SimulatedObjectClasses or ClutterKinds
};

// Places `count` objects (classes in turn from `class_ids`, the first five
// of SimulatedObjectClasses when empty, random sizes within each class's
// range, random orientation) so that each footprint lies inside one of
// `frame_bounds_m` (the frames' ground bounds, x east, y north) at every
// corner of its box, and footprints are at least `min_gap_m` apart.
// Deterministic from `seed`. Throws InputError naming --objects when they do
// not fit.
std::vector<SeabedObject> PlaceSeabedObjects(int count, const std::vector<cv::Rect2d>& frame_bounds_m, uint64_t seed,
                                             double min_gap_m = 1.0, const std::vector<int>& class_ids = {});

// Places `count` clutter pieces (ClutterKinds in turn) like PlaceSeabedObjects,
// at least `min_gap_m` from each other and from `objects`, with a random
// stream of their own (the objects of a seed stay where they were). Throws
// InputError naming --clutter when they do not fit.
std::vector<SeabedObject> PlaceClutter(int count, const std::vector<cv::Rect2d>& frame_bounds_m, uint64_t seed,
                                       const std::vector<SeabedObject>& objects, double min_gap_m = 0.5);

// Paints the objects into the texture (any type SeabedTexture allows): shaded
// bodies lit from the north-west and a soft shadow towards the south-east.
void PaintSeabedObjects(const std::vector<SeabedObject>& objects, SeabedTexture* texture);

// Writes truth_dir/objects.csv (header class,lat,lon,x_m,y_m,size_m) and
// truth_dir/objects.json (the same plus footprints in east/north metres and a
// closed [lon, lat] ring; "classes" lists the five unless a later class is
// painted). Clutter (negative()) goes only to objects.json, under "negatives",
// each with "negative": true; a buried object carries "buried_fraction".
void SaveObjectsTruth(const std::vector<SeabedObject>& objects, const LocalFrame& frame, const std::string& truth_dir);

}  // namespace seamap
