#include "tsuchi/core/interrupt.hpp"

#include <csignal>

namespace tsuchi {

namespace {
volatile std::sig_atomic_t received = 0;

extern "C" void on_signal(int s) { received = s; }
}  // namespace

void install_interrupt_handlers() {
  struct sigaction sa {};
  sa.sa_handler = on_signal;
  sigemptyset(&sa.sa_mask);
  sa.sa_flags = SA_RESETHAND;  // the second signal takes the default action: exit now
  sigaction(SIGINT, &sa, nullptr);
  sigaction(SIGTERM, &sa, nullptr);
}

int pending_interrupt() { return received; }

}  // namespace tsuchi
