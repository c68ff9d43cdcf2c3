#pragma once
// The large configuration of the report benchmark (5,000 parameters, 100 curves of 1,000
// setpoints, 255 command table entries) and a changed copy, for
// lmcfg_bench_report and tests/report/test_report.cpp (header-only so both use it).
// Names carry markup (`<script>alert(1)</script>` in a label; the longest
// prefixes that fit in a curve name, 21 characters, and an entry name, 15) so
// the pages show that every text is escaped.
#include <cmath>
#include <cstdint>
#include <string>

#include "common/layers.hpp"
#include "config/model.hpp"

namespace lmcfg::reportbench {

inline const std::string kScript = "<script>alert(1)</script>";

inline config::Curve make_curve(std::uint32_t id, std::size_t n, const std::string& name,
                                double phase) {
  config::Curve c;
  c.id = id;
  c.info.assign(config::kCurveInfoFull, 0);
  auto put16 = [&](std::size_t off, std::uint32_t v) {
    c.info[off] = static_cast<std::uint8_t>(v);
    c.info[off + 1] = static_cast<std::uint8_t>(v >> 8);
  };
  put16(0, config::kCurveInfoFull);
  put16(2, 0x0003);  // curve, X time, Y position
  put16(4, static_cast<std::uint32_t>(n));
  put16(6, 4);
  for (std::size_t i = 0; i < name.size() && i < 21; ++i)
    c.info[8 + i] = static_cast<std::uint8_t>(name[i]);
  put16(30, id);
  const auto length = static_cast<std::uint32_t>(n * 100);  // 1 ms per setpoint
  put16(32, length & 0xFFFF);
  put16(34, length >> 16);
  put16(36, 0x1A);  // 0.01 ms
  put16(38, 5);     // 0.1 um
  for (std::size_t i = 0; i < n; ++i) {
    const auto v = static_cast<std::int32_t>(std::lround(
        500000.0 *
        (1 - std::cos(6.283185307 * static_cast<double>(i) / static_cast<double>(n) + phase))));
    for (int k = 0; k < 4; ++k)
      c.data.push_back(static_cast<std::uint8_t>(static_cast<std::uint32_t>(v) >> (8 * k)));
  }
  return c;
}

inline config::DriveConfig large_config() {
  config::DriveConfig c;
  c.identity.macid = "11";
  c.identity.product = "large synthetic";
  c.identity.captured_at = "2026-11-23T12:00:00Z";
  c.identity.labels["machine"] = kScript;
  c.identity.labels[kScript] = "label key";
  for (int l = 1; l <= lmcfg::layers::kCount; ++l)
    for (std::uint16_t i = 0; i < 1250; ++i) {
      config::Parameter p;
      p.upid = static_cast<std::uint16_t>(lmcfg::layers::base_upid(l) + 0x100 + i);
      p.value = 1000u + i;
      p.type = 0x05;
      p.default_value = i % 3 ? p.value + 1 : p.value;
      p.name = "Synthetic parameter " + std::to_string(p.upid);  // as a real name's length
      c.layer(l).push_back(p);
    }
  for (std::uint32_t id = 1; id <= 100; ++id) {
    const std::string name = id == 1   ? "<svg onload=alert(1)>"
                             : id == 2 ? "<script>alert(1)</sc"
                                       : "Cam " + std::to_string(id);
    c.curves.push_back(make_curve(id, 1000, name, id * 0.1));
  }
  for (std::uint32_t id = 0; id < 255; ++id) {
    config::CtEntry e;
    e.id = id;
    e.raw.assign(64, 0);
    e.raw[0] = 0x01;
    e.raw[1] = 0xA7;
    const std::uint32_t link = id % 5 == 4 || id == 254 ? 0xFFFF : id + 1;  // chains of 5
    e.raw[2] = static_cast<std::uint8_t>(link), e.raw[3] = static_cast<std::uint8_t>(link >> 8);
    e.raw[4] = 0x00, e.raw[5] = 0x01;  // VAI Go To Pos
    for (std::size_t k = 6; k < 22; ++k) e.raw[k] = static_cast<std::uint8_t>(k * 7 + id);
    const std::string name = id == 0 ? "<script>alert(1" : "Step " + std::to_string(id);
    for (std::size_t k = 0; k < name.size() && k < 15; ++k)
      e.raw[38 + k] = static_cast<std::uint8_t>(name[k]);
    c.ct_entries.push_back(e);
  }
  return c;
}

// `a` with a label, 52 values, 4 + 4 modified-list entries, 11 curves and 11
// command table entries changed or removed.
inline config::DriveConfig large_config_changed(const config::DriveConfig& a) {
  config::DriveConfig b = a;
  b.identity.labels["machine"] = "press 3";
  for (int l = 1; l <= lmcfg::layers::kCount; ++l) {
    auto& ps = b.layer(l);
    for (std::size_t i = 0; i < ps.size(); i += 100) ps[i].value += 7;
    ps.erase(ps.begin() + 5);  // at its default on B
    config::Parameter extra = ps.back();
    extra.upid = static_cast<std::uint16_t>(extra.upid + 1);  // modified on B only
    ps.push_back(extra);
  }
  for (std::uint32_t id = 3; id <= 12; ++id)
    b.curves[id - 1] = make_curve(id, 1000, "Cam " + std::to_string(id), 0.5);
  b.curves[12] = make_curve(13, 500, "Cam 13 short", 0.0);  // another setpoint count
  b.curves.pop_back();                                      // curve 100 removed
  for (std::uint32_t id = 10; id < 20; ++id) b.ct_entries[id].raw[8] ^= 0x55;
  b.ct_entries.pop_back();  // entry 254 removed
  return b;
}

}  // namespace lmcfg::reportbench
