#pragma once
// The paths of chaos and prr for systems with polar maps (seed 3.3.3), private to render/:
// the affine paths stay as they are, and these apply each map through Ifs::apply.
#include <cstdint>
#include <string>
#include <vector>

#include "ifsforge/model/orbit.h"
#include "ifsforge/render/accumulator.h"
#include "ifsforge/render/renderer.h"

namespace ifsforge::polar {

/// One chaos-game job (5.1.1) of `points` points after `skip`, from the stream (seed, job) as
/// the affine jobs draw theirs; the signature of chaos_game.cpp's jobs.
void chaos_job(const Ifs& ifs, const Frame& frame, const MapChain& chain, std::uint64_t points, std::uint64_t skip,
               std::uint64_t seed, std::uint64_t job, Accumulator& acc);

/// Point recursive rendering (5.8.1) of a polar system; `renderer` supplies its parameters.
Raster point_recursive(const Ifs& ifs, const RenderOptions& options, const Renderer& renderer);
/// Jobs [first, last) of it, as Accumulator::encode bytes.
std::string point_recursive_jobs(const Ifs& ifs, const RenderOptions& options, const Renderer& renderer,
                                 std::uint64_t first, std::uint64_t last);

}  // namespace ifsforge::polar
