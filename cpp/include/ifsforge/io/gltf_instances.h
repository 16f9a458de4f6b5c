#pragma once
/// @file Binary glTF 2.0 (.glb) of an instance list for Blender and other DCC tools: the
/// primitives' meshes stored once, one node per instance.
///
/// Blender 3.4's importer has no EXT_mesh_gpu_instancing, but it turns nodes that share a glTF
/// mesh into linked duplicates (objects sharing one mesh datablock), so that is the form used:
/// each primitive's geometry is stored once, and one glTF mesh (sharing it) exists per colour
/// class, because glTF materials belong to meshes, not nodes. Coordinates are converted to
/// glTF's y-up axes by default (see axes.h), which Blender's importer converts back.
#include <string>

#include "ifsforge/geometry/axes.h"
#include "ifsforge/vector/instances.h"

namespace ifsforge {

struct GltfInstanceOptions {
  int segments = 24;  ///< tessellation of the curved primitives
  /// Colours are quantised to this many levels per channel (RGBA); one material and one mesh
  /// per (primitive, colour class) that occurs. 0: one mesh per primitive with a neutral
  /// material, the colours only in the node extras.
  int color_levels = 16;
  /// Node extras: "address" (as "a0.a1..."), "color" (exact sRGB + alpha) and "primitive";
  /// Blender shows them as custom properties (an Attribute node of type Object reads "color").
  bool extras = true;
  std::string name;   ///< the root node; default: the list's name
  Up up = Up::y;      ///< the file's up axis: y is glTF's (z only for readers that ignore the spec)
};

/// @brief Writes `path` atomically: node 0 is the root (named after the system) holding one
/// child node per instance of positive scale, named by its address, with translation, rotation
/// (the instance frame as a quaternion) and uniform scale d. Materials: base colour (the display
/// colour converted to glTF's linear factors, srgb_to_linear), metallic 0, roughness 0.6, double-sided, BLEND when
/// alpha < 1. InputError when no instance has a positive scale.
void write_gltf_instances(const std::string& path, const InstanceList& instances, const GltfInstanceOptions& options = {});

}  // namespace ifsforge
