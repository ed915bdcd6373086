// A program for the interrupt tests (interrupt_test.cpp): installs the
// tools' interrupt handler and then, by its argument,
//   stuck FILE   opens an output FILE (AtomicOutput: its temporary exists)
//                and sleeps without polling, as a read blocked in a library
//                would; prints "ready" when the handler is in place;
//   cleared      raises SIGINT itself, clears the interrupt and goes on for
//                1.5 s, then exits 0.
#include <unistd.h>

#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <thread>

#include "aperture/terrain/interrupt.h"
#include "aperture/terrain/io/atomic_file.h"

int main(int argc, char** argv) {
  aal::installInterruptHandler();
  if (argc == 3 && std::strcmp(argv[1], "stuck") == 0) {
    aal::AtomicOutput output(argv[2]);
    std::ofstream(output.temporaryPath()) << "half of an output";
    std::printf("ready\n");
    std::fflush(stdout);
    for (;;) ::sleep(60);  // never polls the flag
  }
  if (argc == 2 && std::strcmp(argv[1], "cleared") == 0) {
    std::raise(SIGINT);
    aal::clearInterrupt();
    std::this_thread::sleep_for(std::chrono::milliseconds(1500));
    return 0;
  }
  std::fprintf(stderr, "usage: interrupt_probe stuck FILE | cleared\n");
  return 2;
}
