#pragma once
// `lmcfg sim --pty --fast` as a child process: the simulated drive (the demo
// axis unless `extra` names states) on a pseudo-terminal, as a person starts
// it. `tty` is the slave's path the program printed first.
#include <catch2/catch.hpp>
#include <string>
#include <vector>

#include "subprocess.hpp"

namespace lmcfg::test {

struct PtySim {
  Child child;
  std::string tty;
  explicit PtySim(std::vector<std::string> extra = {})
      : child([&] {
          std::vector<std::string> argv{LMCFG_TOOL_PATH, "sim", "--pty", "--fast"};
          argv.insert(argv.end(), extra.begin(), extra.end());
          return argv;
        }()) {
    tty = child.read_line();
    (void)child.read_line();  // the link options line
    REQUIRE(tty.rfind("/dev/pts/", 0) == 0);
  }
};

}  // namespace lmcfg::test
