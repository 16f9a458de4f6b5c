#pragma once
/// @file A volume job result as bytes, for a cluster: what a worker sends back (the sorted
/// voxel sums of its jobs) and the driver merges exactly (VolumeRenderer::run_jobs,
/// VolumeOptions::distribute).
#include <string>

#include "ifsforge/volume/volume_renderer.h"

namespace ifsforge {

/// @brief Compact bytes: voxel keys as ascending deltas (runs along z take one byte each), then
/// the integer sums, all as varints. Sums the volume will not read stay behind: hits unless the
/// density is Hits or there are channels (their means divide by hits), mass unless it is Measure
/// (decoded as 1 hit and no mass: the same volume).
std::string encode_volume_jobs(const VolumeJobsResult& result, VolumeDensity density = VolumeDensity::Measure);
/// @brief The result `encode_volume_jobs` wrote; InputError for anything else.
VolumeJobsResult decode_volume_jobs(const std::string& bytes);

}  // namespace ifsforge
