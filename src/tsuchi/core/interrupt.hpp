#pragma once
// SIGINT / SIGTERM / SIGHUP (a closed terminal) as a request to stop: the handler only records the signal, and the time loop
// looks at it between steps, where the state is whole and can be saved. `timeout` and batch
// schedulers often signal twice in quick succession, so a second signal while the state is not
// yet saved is only counted: the save goes on. Once the checkpoint is complete (interrupt_saved())
// any further signal exits at once with 128 + the signal, as the state is safe; a third signal
// before that ends the program at once by the signal itself, without a checkpoint.
namespace tsuchi {

void install_interrupt_handlers();
// The first signal received since the handlers were installed, or 0.
int pending_interrupt();
// The checkpoint of an interrupted run is complete: from now on a signal exits at once, printing
// `message` (what was saved and how to continue: a signal right after the save must not lose it).
void interrupt_saved(const char* message = "");
// Forget a signal that has been dealt with, so that a program running several simulations (a
// study, the tests) may start the next one: pending_interrupt() is 0 again and a signal is again a
// request to stop, not an exit. The handlers stay as they are.
void clear_interrupt();

}  // namespace tsuchi
