#include "core/stereo/object_georef.h"

#include <gtest/gtest.h>

#include <cmath>

#include "core/util/error.h"

namespace seamap {
namespace {

// object_from_camera for an object whose origin is at `in_camera` (camera
// coordinates) and whose axes are the camera's axes rotated by `camera_from_object`.
Rigid ObjectFromCamera(const Eigen::Vector3d& in_camera, const Eigen::Matrix3d& camera_from_object) {
  Rigid c_from_o = Rigid::Identity();
  c_from_o.linear() = camera_from_object;
  c_from_o.translation() = in_camera;
  return c_from_o.inverse();
}

TEST(ObjectGeoref, ForwardRigOnAVehicleHeadingEast) {
  const LocalFrame frame({43.1, 131.9});
  VehiclePose vehicle;
  vehicle.east_m = 10;
  vehicle.north_m = 20;
  vehicle.depth_m = 30;
  vehicle.heading_deg = 90;  // bow east: the camera looks east, its right is south
  RigMount mount;
  mount.offset_m = {1, 0, 0.5};  // 1 m forward of the navigation point, 0.5 m below it
  const PlacedObject p = PlaceObject(ObjectFromCamera({0, 0, 3}, Eigen::Matrix3d::Identity()), mount, vehicle, frame);
  EXPECT_NEAR(p.local.east, 14, 1e-9);
  EXPECT_NEAR(p.local.north, 20, 1e-9);
  EXPECT_NEAR(p.depth_m, 30.5, 1e-9);
  EXPECT_NEAR(p.heading_deg, 180, 1e-9);  // the object's x axis is the camera's right: south
  const LatLon expected = frame.ToLatLon({14, 20});
  EXPECT_NEAR(p.position.lat, expected.lat, 1e-12);
  EXPECT_NEAR(p.position.lon, expected.lon, 1e-12);
}

TEST(ObjectGeoref, PitchLiftsWhatAForwardCameraSees) {
  const LocalFrame frame({43.1, 131.9});
  VehiclePose vehicle;
  vehicle.depth_m = 30;
  vehicle.pitch_deg = 10;  // bow up: 3 m along the view is above the vehicle
  const PlacedObject p =
      PlaceObject(ObjectFromCamera({0, 0, 3}, Eigen::Matrix3d::Identity()), RigMount{}, vehicle, frame);
  const double s = std::sin(10 * M_PI / 180), c = std::cos(10 * M_PI / 180);
  EXPECT_NEAR(p.local.north, 3 * c, 1e-9);
  EXPECT_NEAR(p.local.east, 0, 1e-9);
  EXPECT_NEAR(p.depth_m, 30 - 3 * s, 1e-9);
}

TEST(ObjectGeoref, DownLookingRigAndAnObjectTurnedOnTheSeabed) {
  const LocalFrame frame({-33.9, 151.2});
  VehiclePose vehicle;
  vehicle.depth_m = 50;
  vehicle.heading_deg = 30;
  RigMount mount;
  mount.looking = RigMount::Looking::kDown;
  // 2 m below the camera; the object's x axis along the camera's x (starboard),
  // turned 20 degrees towards the image top (the bow) about the view axis.
  const Eigen::Matrix3d turned = Eigen::AngleAxisd(-20 * M_PI / 180, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  const PlacedObject p = PlaceObject(ObjectFromCamera({0, 0, 2}, turned), mount, vehicle, frame);
  EXPECT_NEAR(p.depth_m, 52, 1e-9);
  EXPECT_NEAR(std::hypot(p.local.east, p.local.north), 0, 1e-9);
  EXPECT_NEAR(p.heading_deg, 30 + 90 - 20, 1e-9);  // starboard of a bow at 30, turned 20 towards the bow
}

TEST(ObjectGeoref, LookingIsForwardOrDown) {
  EXPECT_EQ(ParseLooking("down", "--rig"), RigMount::Looking::kDown);
  try {
    ParseLooking("up", "--rig");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("--rig"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace seamap
