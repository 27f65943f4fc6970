#pragma once
// SIGINT / SIGTERM as a request to stop: the handler only records the signal, and the time loop
// looks at it between steps, where the state is whole and can be saved. A second signal of the
// same kind kills the program at once (the handler is reset after the first), for a user who does
// not want to wait for the save.
namespace tsuchi {

void install_interrupt_handlers();
// The signal received since the handlers were installed, or 0.
int pending_interrupt();

}  // namespace tsuchi
