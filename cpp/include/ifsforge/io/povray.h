#pragma once
/// @file Running the real POV-Ray 3.7 headless on a scene (scenes: io/pov_scene.h).
#include <string>

#include "ifsforge/core/progress.h"

namespace ifsforge {

/// The image size scenes are framed for and rendered at, unless told otherwise.
inline constexpr int kPovWidth = 800, kPovHeight = 600;

struct PovRenderOptions {
  int width = kPovWidth, height = kPovHeight;
  double antialias = 0.3;  ///< POV-Ray's +A threshold; 0 turns antialiasing off
  int threads = 0;         ///< POV-Ray's render threads (+WT); 0: its default (every core)
  ProgressCallback progress;  ///< polled while POV-Ray runs (fraction 0 until done); false kills it
};

/// @brief Renders `scene` with the real POV-Ray 3.7 (`povray` on PATH) into the PNG `image`,
/// headless (+I +O +W +H -D +FN [+A]), run from an argument list (no shell). POV-Ray runs in the
/// scene's folder (its file-I/O restrictions allow the working directory); it reads the scene
/// through a link of a random name of letters and digits beside it and renders to another such
/// name (POV-Ray re-splits its options at spaces, so the user's names never reach it: any name
/// is data); the image appears atomically and the link goes. FileError when povray is missing, or with POV-Ray's last messages when it
/// fails; Cancelled when the progress callback says stop.
void render_povray(const std::string& scene, const std::string& image, const PovRenderOptions& options = {});

}  // namespace ifsforge
