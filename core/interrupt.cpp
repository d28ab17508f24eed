#include "core/interrupt.h"

#include <atomic>
#include <csignal>

namespace aquaform {

namespace {

std::atomic<bool> g_interrupted{false};
int g_depth = 0;  // live scopes (made and ended on the main thread)

void on_interrupt(int) {
    if (!g_interrupted.exchange(true)) return;
    // A second Ctrl-C: stop now, as killed by SIGINT (the shell says 130). The raised signal waits
    // until this handler returns, then takes the default action.
    std::signal(SIGINT, SIG_DFL);
    std::raise(SIGINT);
}

}  // namespace

InterruptScope::InterruptScope() {
    // Scopes nest (the command's around a library's): the outermost owns the handler and the flag.
    if (g_depth++ > 0) return;
    g_interrupted = false;
    previous_ = std::signal(SIGINT, on_interrupt);
}

InterruptScope::~InterruptScope() {
    if (--g_depth > 0) return;
    std::signal(SIGINT, previous_ == SIG_ERR ? SIG_DFL : previous_);
    g_interrupted = false;
}

bool interrupted() { return g_interrupted.load(); }

}  // namespace aquaform
