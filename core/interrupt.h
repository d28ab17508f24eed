// Ctrl-C for long CPU and GPU loops: while an InterruptScope lives, SIGINT sets a flag that the
// loop polls (interrupted()) so it can stop between units of work and keep what it has written.
// A second Ctrl-C while the first is pending ends the process at once (killed by SIGINT); files
// written through core/file_write.h are then still whole (the one being written is a staged copy).
#pragma once

namespace aquaform {

class InterruptScope {
public:
    InterruptScope();   ///< installs the handler and clears the flag
    ~InterruptScope();  ///< restores the previous handler
    InterruptScope(const InterruptScope&) = delete;
    InterruptScope& operator=(const InterruptScope&) = delete;

private:
    void (*previous_)(int) = nullptr;
};

/// True once SIGINT arrived inside the outermost live InterruptScope (false outside any scope).
bool interrupted();

/// Exit status of a command stopped by Ctrl-C (128 + SIGINT, as shells report it).
constexpr int kExitInterrupted = 130;

}  // namespace aquaform
