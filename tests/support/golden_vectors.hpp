#pragma once
// Loads tests/golden/seed003-captures.txt (extracted from seed 003 by
// scripts/extract-golden.py).
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "common/bytes.hpp"

namespace lmcfg::test {

struct Capture {
  std::string section;  // "9.2"
  int seed_line = 0;    // line in seed 003
  bool tx = false;
  Bytes bytes;
  std::string comment;
  std::string name() const {
    return "seed003 §" + section + " line " + std::to_string(seed_line) + (tx ? " Tx" : " Rx");
  }
};

inline std::vector<Capture> load_seed003_captures() {
  std::ifstream in(std::string(LMCFG_SOURCE_DIR) + "/tests/golden/seed003-captures.txt");
  std::vector<Capture> out;
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    Capture c;
    std::string dir;
    std::istringstream ss(line.substr(0, line.find(';')));
    ss >> c.section >> c.seed_line >> dir;
    c.tx = dir == "Tx";
    std::string rest;
    std::getline(ss, rest);
    c.bytes = from_hex(rest).value();
    if (auto p = line.find(';'); p != std::string::npos) c.comment = line.substr(p + 1);
    out.push_back(std::move(c));
  }
  return out;
}

// tests/golden/seed003-inconsistent.txt: seed line -> the decoder's verdict
// ("frame_short") for the captures that are not self-consistent.
inline std::map<int, std::string> load_seed003_inconsistent() {
  std::ifstream in(std::string(LMCFG_SOURCE_DIR) + "/tests/golden/seed003-inconsistent.txt");
  std::map<int, std::string> m;
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream ss(line);
    int no = 0;
    std::string verdict;
    ss >> no >> verdict;
    m[no] = verdict;
  }
  return m;
}

}  // namespace lmcfg::test
