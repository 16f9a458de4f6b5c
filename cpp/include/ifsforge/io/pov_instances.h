#pragma once
/// @file A POV-Ray 3.7 scene of an instance list (seed 6.2.3.4, 6.5.3.2, 6.6.3): one `union` of
/// the instances, each with its own pigment, framed by a camera and lights from the list's
/// bounds, with ifsforge.inc written beside the scene.
#include <string>

#include "ifsforge/core/progress.h"
#include "ifsforge/io/pov_scene.h"
#include "ifsforge/io/povray.h"
#include "ifsforge/vector/instances.h"

namespace ifsforge {

struct PovSceneOptions {
  std::string title;              ///< first comment line and IFS_Title; default "IFS instances: <name>"
  int width = kPovWidth, height = kPovHeight;  ///< the image the camera is framed for (aspect ratio)
  /// The camera. 2D lists (spatial_dims 2) are seen from straight above: yaw 0, pitch 90 gives
  /// the image axes x right, y up, as `ifsforge render`.
  PovView view;
  PovEnvironment environment;
  /// Add `bounded_by { box {...} }` to the union. POV-Ray 3.7 then keeps the union whole and
  /// tests every member for every ray that enters the box, instead of splitting it into its
  /// automatic bounding hierarchy: tracing gets slower by orders of magnitude (docs/povray.md), so
  /// this is off by default; the bounds are always declared as IFS_Bounds_Min / IFS_Bounds_Max.
  bool bounded_by = false;
  int threads = 0;                ///< formatting threads (0: every core); the bytes never depend on it
  ProgressCallback progress;
};

/// @brief Writes `path` (.pov) and `ifsforge.inc` beside it, both atomically. Instances with a
/// scale of 0 (collapsed by a singular map) are left out; InputError when none is left.
/// Spheres are written as `sphere { q0, d pigment {...} }`, other primitives as
/// `object { IFS_<Primitive> matrix <d e1, d e2, d e3, q0> pigment {...} }`, user meshes as one
/// declared mesh2 each (IFS_Mesh_<file stem>). Names (title, mesh paths) reach only comments
/// and the IFS_Title string, through pov_comment and pov_string. Colours are written as srgb (POV-Ray converts them to its linear
/// working space), with srgbt (transmit = 1 - alpha) where alpha < 1.
void write_pov_scene(const std::string& path, const InstanceList& instances, const PovSceneOptions& options = {});

/// @brief The camera, lights and floor write_pov_scene uses: frame_balls over the instances'
/// bounding balls (2D lists seen from above).
PovFraming frame_instances(const InstanceList& instances, const PovSceneOptions& options);

/// @brief The ifsforge.inc identifier of a built-in primitive ("IFS_Cone", "IFS_Circle_Outline"),
/// or for a user mesh a new one from `names`: IFS_Mesh_<file stem> (pov_identifier), unique in
/// the scene.
std::string pov_primitive_identifier(const Primitive& primitive, PovNames& names);

}  // namespace ifsforge
