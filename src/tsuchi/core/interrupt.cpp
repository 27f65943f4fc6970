#include "tsuchi/core/interrupt.hpp"

#include <atomic>
#include <csignal>
#include <unistd.h>

namespace tsuchi {

namespace {
volatile std::sig_atomic_t received = 0;  // the first signal
volatile std::sig_atomic_t count = 0;     // signals so far
// The checkpoint after the first signal is complete. An atomic, not a sig_atomic_t: the signal may
// be handled on another thread (an OpenMP worker), and the message must be seen whole there.
std::atomic<int> saved{0};
static_assert(std::atomic<int>::is_always_lock_free, "the signal handler reads `saved`");
char saved_message[4096] = "";  // what interrupt_saved() was told, written before `saved` is set

void say(const char* text) {
  std::size_t n = 0;
  while (text[n] != '\0') ++n;
  [[maybe_unused]] const auto written = ::write(STDERR_FILENO, text, n);
}

extern "C" void on_signal(int s) {
  if (received == 0) received = s;
  count = count + 1;
  if (saved.load(std::memory_order_acquire)) {
    say("\ninterrupted: ");
    say(saved_message);
    say("\n");
    ::_exit(128 + s);
  }
  if (count >= 3) {
    say("\ninterrupted a third time before the state was saved: stopping now, without a checkpoint\n");
    std::signal(s, SIG_DFL);
    ::raise(s);
  }
}
}  // namespace

void install_interrupt_handlers() {
  struct sigaction sa {};
  sa.sa_handler = on_signal;
  sigemptyset(&sa.sa_mask);
  sigaddset(&sa.sa_mask, SIGINT);  // one handler at a time: the count stays exact
  sigaddset(&sa.sa_mask, SIGTERM);
  sigaddset(&sa.sa_mask, SIGHUP);
  sa.sa_flags = SA_RESTART;  // a write in progress goes on rather than failing with EINTR
  sigaction(SIGINT, &sa, nullptr);
  sigaction(SIGTERM, &sa, nullptr);
  // A closed terminal or SSH session: the same request to stop, with a checkpoint, not a kill.
  sigaction(SIGHUP, &sa, nullptr);
}

int pending_interrupt() { return received; }

void interrupt_saved(const char* message) {
  if (message[0] == '\0') message = "the state was saved; stopping now";
  std::size_t n = 0;  // a longer message is cut (the restart command is far shorter in practice)
  for (; message[n] != '\0' && n + 1 < sizeof saved_message; ++n) saved_message[n] = message[n];
  saved_message[n] = '\0';
  saved.store(1, std::memory_order_release);  // the message is whole before the handler may read it
}

void clear_interrupt() {
  saved.store(0, std::memory_order_release);
  count = 0;
  received = 0;
}

}  // namespace tsuchi
