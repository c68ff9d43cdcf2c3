#include "confirm.hpp"

#include <unistd.h>

#include <cstdio>
#include <iostream>

namespace lmcfg::cli {

Result<ops::Consent> confirm(const std::string& question, const std::string& action, bool yes) {
  if (yes) return ops::Consent::go;
  if (!::isatty(STDIN_FILENO)) {
    return Error(Errc::invalid_argument, "refusing to " + action +
                                             " without --yes when stdin is not a terminal; "
                                             "nothing written");
  }
  std::fprintf(stderr, "%s [y/N] ", question.c_str());
  std::fflush(stderr);
  std::string answer;
  std::getline(std::cin, answer);
  if (answer == "y" || answer == "Y" || answer == "yes") return ops::Consent::go;
  return ops::Consent::declined;
}

}  // namespace lmcfg::cli
