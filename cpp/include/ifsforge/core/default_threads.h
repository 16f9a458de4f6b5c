#pragma once
/// @file The process-wide meaning of threads = 0 ("automatic") for every parallel call
/// (resolve_threads in parallel.h reads it).

namespace ifsforge {

/// @brief The thread count every call asking for 0 gets; 0 restores the hardware concurrency.
/// Outputs do not depend on it (a host such as Blender leaves cores to its UI). InputError if < 0.
void set_default_threads(int threads);

}  // namespace ifsforge
