// What `aquaform run` prints at start (runner/run_files.h: what it writes besides its frames).
#pragma once

#include "session/simulation_session.h"

namespace aquaform {
class PbfSolver;
namespace gpu {
class Context;
}
}  // namespace aquaform

namespace aquaform::cli {

/// Prints the scene's size, the passes it enables and the GPU memory of every buffer.
void print_run_header(const gpu::Context& ctx, const PbfSolver& solver);
/// Prints a session's control: its meshes' notes, the strength, and (on stderr) its warning.
void print_control_summary(const session::ControlSummary& summary, const char* command);

}  // namespace aquaform::cli
