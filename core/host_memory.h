// How much host memory a command may plan to use, so that work too large for the machine is
// refused before it allocates (with the need, this figure and a fix) instead of swapping or
// being killed.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

namespace aquaform {

/// Bytes of host memory available to this process: the kernel's MemAvailable, lowered to what
/// is left under the process's cgroup v2 limit (a container, a SLURM job) and to
/// AQUAFORM_HOST_MEMORY when set (a byte count with an optional K, M or G suffix: "8G"). nullopt
/// when none of them can be read. Throws Failure (bad input) for an AQUAFORM_HOST_MEMORY that is
/// not a size.
std::optional<uint64_t> available_host_memory();

/// A byte count as messages say it: whole MB (2^20 bytes), and below 1 MB in KiB or bytes, so
/// that a small figure never reads "0 MB".
std::string memory_size_text(uint64_t bytes);

/// "N MB are available", for the figure available_host_memory() returned; when
/// AQUAFORM_HOST_MEMORY set it, the message says so and how to change it
/// ("1 KiB are available (AQUAFORM_HOST_MEMORY=1K; unset it or raise it)").
std::string available_memory_text(uint64_t bytes);

}  // namespace aquaform
