#pragma once
// Format version 1 and its migration to version 2.
//
// Version 1 (lmcfg 0.0.x) stored one flat parameter list without layers,
// UPIDs and values as decimal numbers (values of signed parameters could be
// negative), blocks as one hex string each, link settings and provenance in a
// "drive" object, and no scope (it always captured the modified parameters of
// every layer, all curves and the command table).
//
// Both readers parse a v1 file into ConfigV1 (each item carries its location
// in the file as text, for messages); migrate_v1_to_v2 does the rest.
#include <cstdint>
#include <string>
#include <vector>

#include "common/bytes.hpp"
#include "common/result.hpp"
#include "config/model.hpp"

namespace lmcfg::config {

struct ConfigV1 {
  struct Param {
    std::int64_t upid = 0;   // decimal in the file
    std::int64_t value = 0;  // decimal, -2^31 .. 2^32-1
    std::string where;       // "f.json:7:9: /parameters/3" or "f.xml: /lmcfg/parameters/param[4]"
  };
  struct Block {
    std::int64_t id = 0;
    Bytes info;  // curves only
    Bytes data;  // curve data / CT entry bytes
    std::string where;
  };
  std::string field_sep = "/";  // between an item's `where` and a field: "/" JSON, "/@" XML
  std::string macid, port, baud, parity, stop_bits, checksum;
  std::string tool_version, captured_at;
  std::vector<Param> params;
  std::vector<Block> curves;
  std::vector<Block> ct_entries;
};

// Puts each parameter in the layer of its UPID range, turns values into the
// raw 32-bit field (negative -> two's complement), sets the scope v1 implied
// (all layers, modified-only, curves and CT captured), then validates.
// Errors name the v1 item's location. Result is canonicalized.
Result<DriveConfig> migrate_v1_to_v2(const ConfigV1& v1);

}  // namespace lmcfg::config
