#pragma once
// Workloads and the protocol-minimum model for lmcfg_bench_wire and
// tests/ops/test_perf_telegrams.cpp (header-only so both can use it).
//
// The minimum of an operation is the set of telegrams the operation cannot
// avoid on the LinRS protocol (seed 003), each costed exactly as the simulator's
// documented wire model does (docs/simulator.md "Timing model"):
//   request wire time + turnaround + the operation's duration + answer wire time,
//   wire time = bytes * (1 start + 8 data + parity + stop) / baud.
// Telegram sizes come from encoding the shortest legal form of each request and
// its answer with the codec at the drive's checksum and default-response layout.
// The model reads the target's *true* state (the simulated drive), never the
// tool's plan. Definitions: docs/performance.md "The protocol minimum".
#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "codec/frame.hpp"
#include "codec/messages.hpp"
#include "config/model.hpp"
#include "db/database.hpp"
#include "db/value.hpp"
#include "ops/backup.hpp"
#include "ops/restore.hpp"
#include "sim/drive.hpp"
#include "sim/link.hpp"

namespace lmcfg::benchwire {

// ---------------------------------------------------------------- workloads

struct HeavySpec {
  std::size_t upids = 2500;    // all four layers
  std::size_t modified = 300;  // ROM values that differ from their defaults
  std::size_t curves = 20;
  std::size_t setpoints = 500;  // per curve, 4 bytes each
  std::size_t ct_entries = 64;  // 64 bytes each
  std::uint32_t salt = 0;       // changes values, curve and CT contents
};

inline Bytes curve_info(std::uint16_t id, std::size_t setpoints, const std::string& name) {
  Bytes b(config::kCurveInfoFull, 0);
  auto put16 = [&](std::size_t off, std::uint32_t v) {
    b[off] = static_cast<std::uint8_t>(v);
    b[off + 1] = static_cast<std::uint8_t>(v >> 8);
  };
  put16(0, static_cast<std::uint32_t>(b.size()));
  put16(2, 0x0003);  // curve, X time, Y position
  put16(4, static_cast<std::uint32_t>(setpoints));
  put16(6, 4);
  for (std::size_t i = 0; i < name.size() && i < 21; ++i)
    b[8 + i] = static_cast<std::uint8_t>(name[i]);
  put16(30, id);
  const std::uint32_t length =
      static_cast<std::uint32_t>(setpoints) * 100;  // 1 ms per setpoint, 10 us units
  put16(32, length & 0xFFFF);
  put16(34, length >> 16);
  put16(36, 0x1A);
  put16(38, 5);
  return b;
}

inline Bytes curve_data(std::size_t setpoints, std::uint32_t salt) {
  Bytes d;
  d.reserve(setpoints * 4);
  for (std::size_t i = 0; i < setpoints; ++i) {
    const auto v = static_cast<std::uint32_t>(i * 1000 + salt * 7);
    for (int k = 0; k < 4; ++k) d.push_back(static_cast<std::uint8_t>(v >> (8 * k)));
  }
  return d;
}

inline Bytes ct_entry(std::uint16_t id, std::uint32_t salt) {
  Bytes e(64, 0);
  e[0] = 0x01;
  e[1] = static_cast<std::uint8_t>(id);
  for (std::size_t i = 2; i < 38; ++i) e[i] = static_cast<std::uint8_t>(i * 13 + id + salt);
  char name[17];
  std::snprintf(name, sizeof name, "Entry %03u/%u", static_cast<unsigned>(id),
                static_cast<unsigned>(salt % 10));
  for (std::size_t i = 0; i < 16 && name[i]; ++i) e[38 + i] = static_cast<std::uint8_t>(name[i]);
  return e;
}

// A drive with `spec.upids` synthetic UPIDs spread over the four layers (every
// fifth one a variable without ROM-write usage), `spec.modified` ROM values off
// their defaults (spread evenly), curves 1..n and CT entries 0..n-1 in RAM and flash.
inline sim::DriveState heavy_state(const HeavySpec& spec) {
  sim::DriveState s;
  const std::size_t per_layer[4] = {
      spec.upids * 2 / 10, spec.upids * 36 / 100, spec.upids * 28 / 100,
      spec.upids - spec.upids * 2 / 10 - spec.upids * 36 / 100 - spec.upids * 28 / 100};
  std::vector<std::uint16_t> rom_writable;
  for (int l = 0; l < 4; ++l) {
    for (std::size_t i = 0; i < per_layer[l]; ++i) {
      sim::Parameter p;
      p.upid = static_cast<std::uint16_t>(l * 0x1000 + 0x100 + i);
      p.name = "synthetic";
      switch (i % 4) {
        case 0:
          p.type = type_code(TypeCode::UInt16), p.min = 0, p.max = 65535, p.def = 100;
          break;
        case 1:
          p.type = type_code(TypeCode::SInt32), p.min = static_cast<std::uint32_t>(-1'000'000),
          p.max = 1'000'000, p.def = 0;
          break;
        case 2:
          p.type = type_code(TypeCode::UInt32), p.min = 0, p.max = 0xFFFFFFFF, p.def = 5000;
          break;
        default:
          p.type = type_code(TypeCode::UInt8), p.min = 0, p.max = 255, p.def = 1;
          break;
      }
      p.address_usage = (i % 5 == 4)
                            ? static_cast<std::uint16_t>(sim::au::ram_read | sim::au::not_for_hash)
                            : sim::au::parameter;
      p.rom = p.ram = p.def;
      if (p.has_rom()) rom_writable.push_back(p.upid);
      s.params[p.upid] = p;
    }
  }
  const std::size_t n = std::min(spec.modified, rom_writable.size());
  for (std::size_t k = 0; k < n; ++k) {
    auto& p = s.params[rom_writable[k * rom_writable.size() / std::max<std::size_t>(n, 1)]];
    p.rom = p.ram = p.def + 1 + static_cast<std::uint32_t>((k + spec.salt) % 50);
  }
  for (std::size_t c = 1; c <= spec.curves; ++c) {
    const auto id = static_cast<std::uint16_t>(c);
    sim::Curve cv{curve_info(id, spec.setpoints, "Heavy " + std::to_string(c)),
                  curve_data(spec.setpoints, spec.salt + id)};
    s.curves_flash[id] = cv;
    s.curves_ram[id] = cv;
  }
  for (std::size_t e = 0; e < spec.ct_entries; ++e) {
    const auto id = static_cast<std::uint16_t>(e);
    s.ct_flash[id] = s.ct_ram[id] = ct_entry(id, spec.salt);
  }
  return s;
}

// A used spare of the same type: same UPID set, `leftover` other ROM values
// modified (spread with another stride, so some fall on UPIDs the source also
// modifies, with other values), a few other curves and CT entries.
inline sim::DriveState heavy_spare(const HeavySpec& spec, std::size_t modified, std::size_t curves,
                                   std::size_t entries) {
  HeavySpec sp = spec;
  sp.modified = 0;
  sp.curves = 0;
  sp.ct_entries = 0;
  sim::DriveState s = heavy_state(sp);
  std::vector<std::uint16_t> rom_writable;
  for (auto& [upid, p] : s.params)
    if (p.has_rom()) rom_writable.push_back(upid);
  for (std::size_t k = 0; k < modified && !rom_writable.empty(); ++k) {
    const std::size_t idx = (k * 7 + 3) % rom_writable.size();
    auto& p = s.params[rom_writable[idx]];
    p.rom = p.ram = p.def + 60 + static_cast<std::uint32_t>(k % 20);
  }
  for (std::size_t c = 0; c < curves; ++c) {
    const auto id = static_cast<std::uint16_t>(30 + c);
    sim::Curve cv{curve_info(id, 100, "Spare " + std::to_string(id)), curve_data(100, 99)};
    s.curves_flash[id] = s.curves_ram[id] = cv;
  }
  for (std::size_t e = 0; e < entries; ++e) {
    const auto id = static_cast<std::uint16_t>(100 + e);
    s.ct_flash[id] = s.ct_ram[id] = ct_entry(id, 77);
  }
  return s;
}

// The same drive straight from the factory: every ROM value at its default, no
// curves, no command table.
inline sim::DriveState factory_fresh(sim::DriveState s) {
  for (auto& [upid, p] : s.params) {
    if (p.has_rom()) p.rom = p.def;
    p.ram = p.rom;
  }
  s.curves_flash.clear();
  s.curves_ram.clear();
  s.ct_flash.clear();
  s.ct_ram.clear();
  return s;
}

// --------------------------------------------------------------- the model

struct Cost {
  std::uint64_t telegrams = 0;
  std::int64_t ns = 0;
  std::int64_t request_ns = 0;  // part of ns: wire time of the requests
  Cost& operator+=(const Cost& o) {
    telegrams += o.telegrams;
    ns += o.ns;
    request_ns += o.request_ns;
    return *this;
  }
  friend Cost operator+(Cost a, const Cost& b) { return a += b; }
  double seconds() const { return static_cast<double>(ns) / 1e9; }
};

class WireModel {
 public:
  explicit WireModel(const sim::DriveState& d) : d_(d) {}

  // One exchange: request, turnaround + duration, answer.
  Cost exchange(const codec::Telegram& req, const codec::Telegram& answer,
                std::int64_t duration_us = 0) const {
    const auto rq = codec::encode(req, d_.checksum).value().size();
    const auto an = codec::encode(answer, d_.checksum).value().size();
    const auto tx = sim::wire_time_ns(rq, d_.link);
    return Cost{
        1, tx + (d_.timing.turnaround_us + duration_us) * 1000 + sim::wire_time_ns(an, d_.link),
        tx};
  }
  // Request of main 04/05/08 answered with the 7-byte "state, id, value" body.
  Cost id_value(const codec::Telegram& req, std::int64_t duration_us = 0) const {
    return exchange(req, codec::make_id_value(d_.macid, 0x50, 0, 0, 0), duration_us);
  }
  Cost cfg(codec::CfgOp op, std::uint16_t upid = 0) const {
    return id_value(codec::make_cfg(d_.macid, op, upid));
  }
  Cost cfg_write(std::uint16_t upid) const {
    return id_value(codec::make_cfg_write(d_.macid, upid, 0));
  }
  Cost curve(codec::CurveOp op, std::uint16_t id, std::int64_t duration_us = 0) const {
    return id_value(codec::make_curve(d_.macid, op, id), duration_us);
  }
  Cost ct(codec::CtOp op, std::uint16_t id) const {
    return id_value(codec::make_ct(d_.macid, op, id));
  }
  std::uint8_t id() const { return d_.macid; }
  const sim::DriveState& drive() const { return d_; }

  // start + one get-next per modified UPID (the last one answered C6, §10.2); an
  // empty list still costs one get-next (answered C6).
  Cost modified_list(std::size_t n) const {
    Cost c = cfg(codec::CfgOp::start_modified);
    for (std::size_t i = 0; i < std::max<std::size_t>(n, 1); ++i)
      c += cfg(codec::CfgOp::next_modified);
    return c;
  }
  // start + one get-next per UPID + the get-next answered C6, which repeats
  // the last UPID (§10.3) or, for an empty layer, ends the list at once.
  Cost upid_list(std::size_t n) const {
    Cost c = cfg(codec::CfgOp::start_upid_list);
    for (std::size_t i = 0; i < n + 1; ++i) c += cfg(codec::CfgOp::next_upid);
    return c;
  }
  // 100 "read sizes" probes (no message lists curve IDs, §11) + info and data
  // chunk reads of each existing curve (4 bytes per telegram).
  Cost read_curves(const std::vector<std::pair<std::size_t, std::size_t>>& sizes,
                   std::uint16_t max_id) const {
    Cost c;
    for (std::uint16_t i = 1; i <= max_id; ++i) c += curve(codec::CurveOp::read_sizes, i);
    for (auto [info, data] : sizes) {
      for (std::size_t k = 0; k < chunks(info); ++k) c += curve(codec::CurveOp::read_info, 1);
      for (std::size_t k = 0; k < chunks(data); ++k) c += curve(codec::CurveOp::read_data, 1);
    }
    return c;
  }
  // 8 defined-list telegrams in the table's LEN 05 form (§12, a seed erratum) + per
  // entry a setup read and its 4-byte chunks.
  Cost read_ct(const std::vector<std::size_t>& entry_sizes) const {
    Cost c;
    for (std::uint16_t b = 0; b < 8; ++b)
      c += id_value(codec::make_ct_defined_list(d_.macid, b, false));
    for (auto n : entry_sizes) {
      c += ct(codec::CtOp::setup_read, 0);
      for (std::size_t k = 0; k < chunks(n); ++k) c += ct(codec::CtOp::read_data, 0);
    }
    return c;
  }
  static std::size_t chunks(std::size_t n) { return (n + 3) / 4; }

 private:
  const sim::DriveState& d_;
};

inline std::map<std::uint16_t, std::uint32_t> modified_of(const sim::DriveState& d, int layer) {
  std::map<std::uint16_t, std::uint32_t> m;
  for (const auto& [upid, p] : d.params)
    if (static_cast<int>(sim::layer_of(upid)) == layer && p.modified()) m[upid] = p.rom;
  return m;
}

// Backup (modified parameters, all layers, curves, CT) of drive `d`: per
// modified UPID a type and a default query when the database (db) does not
// know them and the backup records them (opt.ask_drive).
inline Cost min_backup(const sim::DriveState& d, const ops::BackupOptions& opt = {},
                       const db::Database& db = db::Database::empty()) {
  WireModel w(d);
  Cost c;
  for (int l = 1; l <= 4; ++l) {
    if (!opt.layers[static_cast<std::size_t>(l - 1)]) continue;
    const auto mods = modified_of(d, l);
    c += w.modified_list(mods.size());
    if (!opt.ask_drive) continue;
    for (const auto& [upid, value] : mods) {
      const db::Parameter* p = db.find(upid);
      if (!(p && p->spec.type)) c += w.cfg(codec::CfgOp::get_type, upid);
      if (!(p && p->default_value)) c += w.cfg(codec::CfgOp::get_default, upid);
    }
  }
  if (opt.curves) {
    std::vector<std::pair<std::size_t, std::size_t>> sizes;
    for (const auto& [id, cv] : d.curves_ram)
      if (id >= 1 && id <= opt.max_curve_id) sizes.emplace_back(cv.info.size(), cv.data.size());
    c += w.read_curves(sizes, opt.max_curve_id);
  }
  if (opt.command_table) {
    std::vector<std::size_t> sizes;
    for (const auto& [id, e] : d.ct_ram) sizes.push_back(e.size());
    c += w.read_ct(sizes);
  }
  return c;
}

struct RestoreCost {
  Cost plan, execute, verify;
  Cost without_verify() const { return plan + execute; }
  Cost total() const { return plan + execute + verify; }
};

// Restore of `file` onto the drive `t` (its state before the restore), as
// docs/restore.md plans it: compare first, write only what differs, check what is
// written against the target.
//  plan:    per restored layer the target's modified list; per file value the
//           target does not list and whose default is unknown or equal to the
//           file's value, one ROM read (05h 01h). Per parameter that will be
//           written: its type (the target's UPID list of the layer when the
//           database lacks an address usage, else 05h 04h) and the target's
//           min and max (05h 05h/06h, always: the target is the truth); per
//           leftover written back, the target's default (05h 07h). The command
//           table: the defined list and every entry of the target; curves: the
//           100 size probes, each target curve's info block, and its data block
//           when the file has that curve with the same info block and size.
//  execute: nothing at all when nothing differs. Else stop MC; per layer the
//           cheaper of (a) writing each leftover back to its default and (b)
//           defaulting the layer (1 telegram + its duration) and writing again
//           what the target already held; the differing values; per command
//           table entry that differs or is only on the target a delete (08h
//           02h), per entry to write setup + chunks, one save (+ flash
//           duration) if any; the same for curves (04h 02h, add + info + data
//           chunks, one save); a reset when ROM values changed, else an MC start.
//  verify:  none when nothing was written (the plan's reads compared every
//           item); else the modified list of each layer (+ a ROM read per
//           value at its default), the CT list and every entry, the 100 curve
//           probes and every curve's blocks.
inline RestoreCost min_restore(const sim::DriveState& t, const config::DriveConfig& file,
                               const db::Database& db, const ops::RestoreOptions& opt = {}) {
  WireModel w(t);
  RestoreCost rc;
  auto is_comm = [&](std::uint16_t upid) { return ops::is_comm_parameter(db, upid); };
  auto known_default = [&](const config::Parameter& p) -> std::optional<std::uint32_t> {
    const db::Parameter* d = db.find(p.upid);
    if (d && d->default_value) return static_cast<std::uint32_t>(*d->default_value);
    return p.default_value;
  };
  bool rom_changed = false;
  Cost changes;  // execute without MC stop / start / reset
  std::size_t verify_rom_reads = 0;
  std::vector<std::size_t> modified_after;
  // Is MC running? (one default response; a stopped MC means a half-done run)
  rc.plan +=
      w.exchange(codec::make_response_request(w.id(), codec::ResponseRequest::default_response),
                 codec::make_default_response(w.id(), codec::DefaultResponse{}, t.layout));
  for (int l = 1; l <= 4; ++l) {
    if (!file.scope.layers[static_cast<std::size_t>(l - 1)]) continue;
    const auto target = modified_of(t, l);
    rc.plan += w.modified_list(target.size());
    std::map<std::uint16_t, std::uint32_t> after;  // what the layer must hold afterwards
    std::vector<const config::Parameter*> writes;
    std::size_t same = 0, keep = 0, leftovers = 0;
    std::set<std::uint16_t> restored;
    for (const auto& p : file.layer(l)) {
      if (is_comm(p.upid) && !opt.include_comm) continue;
      restored.insert(p.upid);
      after[p.upid] = p.value;
      if (auto it = target.find(p.upid); it != target.end()) {
        if (it->second == p.value)
          ++same;
        else
          writes.push_back(&p);
        continue;
      }
      const auto def = known_default(p);
      if (def && *def != p.value) {
        writes.push_back(&p);
        continue;
      }
      rc.plan += w.cfg(codec::CfgOp::read_rom, p.upid);
      const auto tp = t.params.find(p.upid);
      if (tp == t.params.end() || tp->second.rom != p.value) writes.push_back(&p);
    }
    for (const auto& [upid, value] : target) {
      if (restored.count(upid)) continue;
      if (is_comm(upid) && !opt.include_comm) {
        ++keep;
        after[upid] = value;
      } else {
        ++leftovers;
      }
    }
    const bool walk_list = std::any_of(writes.begin(), writes.end(), [&](auto* p) {
      const db::Parameter* d = db.find(p->upid);
      return !(d && d->address_usage);
    });
    if (walk_list) {
      std::size_t listed = 0;
      for (const auto& [upid, p] : t.params)
        listed += static_cast<int>(sim::layer_of(upid)) == l ? 1 : 0;
      rc.plan += w.upid_list(listed);
    }
    for (const auto* p : writes) {
      if (!walk_list) rc.plan += w.cfg(codec::CfgOp::get_type, p->upid);
      const auto tp =
          t.params.count(p->upid) ? t.params.at(p->upid).type : type_code(TypeCode::UInt16);
      const auto code = db::type_from_code(tp);
      if (!(code && db::is_text_type(*code))) {
        rc.plan += w.cfg(codec::CfgOp::get_min, p->upid);
        rc.plan += w.cfg(codec::CfgOp::get_max, p->upid);
      }
      changes += w.cfg_write(p->upid);
    }
    // (a) each leftover: the target's default (a read: plan) and a write;
    // (b) default the layer and write again what the target held.
    Cost a_plan, a_exec, b_exec;
    for (std::size_t i = 0; i < leftovers; ++i) {
      a_plan += w.cfg(codec::CfgOp::get_default, 0);
      a_exec += w.cfg_write(0);
    }
    b_exec += w.id_value(codec::make_cfg_default_layer(w.id(), l), t.timing.defaulting_us);
    for (std::size_t i = 0; i < same + keep; ++i) b_exec += w.cfg_write(0);
    const bool use_b = opt.default_first && leftovers > 0 && b_exec.ns < (a_plan + a_exec).ns;
    if (use_b) {
      changes += b_exec;
    } else {
      rc.plan += a_plan;
      changes += a_exec;
    }
    rom_changed = rom_changed || use_b || leftovers > 0 || !writes.empty();
    // Afterwards the layer's modified list holds the values that differ from
    // their defaults; values at their default need a ROM read.
    std::size_t listed = 0;
    for (const auto& [upid, value] : after) {
      const auto it = t.params.find(upid);
      const bool at_default = it != t.params.end() && it->second.def == value;
      at_default ? ++verify_rom_reads : ++listed;
    }
    modified_after.push_back(listed);
  }
  if (file.scope.command_table) {
    std::vector<std::size_t> sizes;
    for (const auto& [id, e] : t.ct_ram) sizes.push_back(e.size());
    rc.plan += w.read_ct(sizes);
    bool any = false;
    for (const auto& [id, raw] : t.ct_ram) {
      const auto* e = file.find_ct_entry(id);
      if (!e || e->raw != raw) {
        changes += w.id_value(codec::make_ct(w.id(), codec::CtOp::delete_one, id));
        any = true;
      }
    }
    for (const auto& e : file.ct_entries) {
      auto it = t.ct_ram.find(static_cast<std::uint16_t>(e.id));
      if (it != t.ct_ram.end() && it->second == e.raw) continue;
      changes +=
          w.id_value(codec::make_ct_setup_write(w.id(), static_cast<std::uint16_t>(e.id), 64));
      for (std::size_t k = 0; k < WireModel::chunks(e.raw.size()); ++k)
        changes += w.id_value(codec::make_ct_write(w.id(), 0, {0, 0, 0, 0}));
      any = true;
    }
    // A table is saved only when an entry of it is written or deleted
    // (ops/restore_plan.cpp; a flash that differs is caught by the verify).
    if (any)
      changes +=
          w.id_value(codec::make_ct(w.id(), codec::CtOp::save_to_flash), t.timing.flash_save_us);
  }
  if (file.scope.curves) {
    bool any = false;
    for (std::uint16_t id = 1; id <= opt.max_curve_id; ++id) {
      rc.plan += w.curve(codec::CurveOp::read_sizes, id);
      const config::Curve* fc = file.find_curve(id);
      auto it = t.curves_ram.find(id);
      if (it == t.curves_ram.end()) continue;
      const auto& cv = it->second;
      for (std::size_t k = 0; k < WireModel::chunks(cv.info.size()); ++k)
        rc.plan += w.curve(codec::CurveOp::read_info, id);
      if (fc && fc->info == cv.info && fc->data.size() == cv.data.size()) {
        for (std::size_t k = 0; k < WireModel::chunks(cv.data.size()); ++k)
          rc.plan += w.curve(codec::CurveOp::read_data, id);
        if (fc->data == cv.data) continue;
      }
      changes += w.curve(codec::CurveOp::delete_one, id);
      any = true;
    }
    for (const auto& fc : file.curves) {
      auto it = t.curves_ram.find(static_cast<std::uint16_t>(fc.id));
      if (it != t.curves_ram.end() && it->second.info == fc.info && it->second.data == fc.data)
        continue;
      changes += w.id_value(codec::make_curve_add(w.id(), static_cast<std::uint16_t>(fc.id), 0, 0));
      for (std::size_t k = 0; k < WireModel::chunks(fc.info.size()); ++k)
        changes += w.id_value(
            codec::make_curve_write(w.id(), codec::CurveOp::write_info, 0, {0, 0, 0, 0}));
      for (std::size_t k = 0; k < WireModel::chunks(fc.data.size()); ++k)
        changes += w.id_value(
            codec::make_curve_write(w.id(), codec::CurveOp::write_data, 0, {0, 0, 0, 0}));
      any = true;
    }
    if (any)
      changes += w.id_value(codec::make_curve(w.id(), codec::CurveOp::save_to_flash),
                            t.timing.flash_save_us);
  }
  if (changes.telegrams == 0) return rc;  // nothing to do: no write, no verify
  rc.execute +=
      w.exchange(codec::make_program(w.id(), codec::ProgramOp::stop_mc),
                 codec::make_default_response(w.id(), codec::DefaultResponse{}, t.layout));
  rc.execute += changes;
  if (opt.reset_after && rom_changed) {
    rc.execute += w.exchange(codec::make_program(w.id(), codec::ProgramOp::reset_after_completion),
                             codec::make_program_response(w.id(), 0), t.timing.reset_us);
  } else {
    rc.execute += w.exchange(codec::make_program(w.id(), codec::ProgramOp::start_after_completion),
                             codec::make_program_response(w.id(), 0), t.timing.start_us);
  }
  // verify
  for (auto n : modified_after) rc.verify += w.modified_list(n);
  for (std::size_t i = 0; i < verify_rom_reads; ++i) rc.verify += w.cfg(codec::CfgOp::read_rom, 0);
  if (file.scope.command_table) {
    std::vector<std::size_t> sizes;
    for (const auto& e : file.ct_entries) sizes.push_back(e.raw.size());
    rc.verify += w.read_ct(sizes);
  }
  if (file.scope.curves) {
    std::vector<std::pair<std::size_t, std::size_t>> sizes;
    for (const auto& cv : file.curves) sizes.emplace_back(cv.info.size(), cv.data.size());
    rc.verify += w.read_curves(sizes, opt.max_curve_id);
  }
  return rc;
}

}  // namespace lmcfg::benchwire
