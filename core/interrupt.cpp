#include "core/interrupt.h"

#include <atomic>
#include <csignal>

namespace aquaform {

namespace {

std::atomic<bool> g_interrupted{false};

void on_interrupt(int) {
    if (g_interrupted.exchange(true)) std::signal(SIGINT, SIG_DFL);  // a second Ctrl-C: stop now
}

}  // namespace

InterruptScope::InterruptScope() {
    g_interrupted = false;
    previous_ = std::signal(SIGINT, on_interrupt);
}

InterruptScope::~InterruptScope() {
    std::signal(SIGINT, previous_ == SIG_ERR ? SIG_DFL : previous_);
    g_interrupted = false;
}

bool interrupted() { return g_interrupted.load(); }

}  // namespace aquaform
