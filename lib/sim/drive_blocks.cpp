// The simulated drive's block transfers: motion curves (LinRS §11) and the
// command table (LinRS §12), with the flash save's duration. The rest of the
// drive is in drive.cpp.
#include <algorithm>

#include "codec/requests.hpp"
#include "sim/drive.hpp"

namespace lmcfg::sim {

using codec::CtOp;
using codec::CurveOp;
using codec::Telegram;
namespace st = codec::state;

// ---- block transfers (§11, §12) ----------------------------------------------

std::uint8_t Drive::block_write(Bytes& target, XferKind kind, std::uint16_t key, ByteView chunk) {
  if (xfer_.kind != kind || xfer_.key != key) xfer_ = Transfer{kind, key, 0};
  for (std::size_t i = 0; i < 4 && i < chunk.size(); ++i)
    if (xfer_.offset + i < target.size()) target[xfer_.offset + i] = chunk[i];
  xfer_.offset += 4;
  if (xfer_.offset >= target.size()) {
    xfer_ = {};
    return st::ok;
  }
  return st::more_data;
}

std::uint8_t Drive::block_read(const Bytes& source, XferKind kind, std::uint16_t key,
                               std::uint32_t& out) {
  if (xfer_.kind != kind || xfer_.key != key) xfer_ = Transfer{kind, key, 0};
  Bytes four(4, 0);
  for (std::size_t i = 0; i < 4; ++i) {
    if (xfer_.offset + i < source.size())
      four[i] = source[xfer_.offset + i];
    else if (s_.options.stale_block_padding)
      four[i] = stale_++;  // what the drive's buffer held before: not part of the block
  }
  out = get_u32le(four, 0);
  xfer_.offset += 4;
  if (xfer_.offset >= source.size()) {
    xfer_ = {};
    return st::ok;
  }
  return st::more_data;
}

std::int64_t Drive::flash_save_duration_us() {
  if (slow_flash_) {
    slow_flash_ = false;
    return s_.timing.flash_save_max_us;
  }
  return s_.timing.flash_save_us;
}

std::optional<Answer> Drive::on_curve(const Telegram& t, std::int64_t now) {
  const std::uint8_t sub = codec::expected_answer_sub(t);  // 40h for every curve request
  const auto& o = s_.options;
  const auto op = static_cast<CurveOp>(t.sub);
  switch (op) {
    case CurveOp::save_to_flash:
      if (s_.mc_running) return finish(id_value(sub, o.flash_refused_state, 0, 0), 0, now);
      s_.curves_flash = s_.curves_ram;
      ++stats_.flash_saves;
      return finish_long(id_value(sub, st::ok, 0, 0), flash_save_duration_us(), now);
    case CurveOp::delete_all:
      s_.curves_ram.clear();
      xfer_ = {};
      return finish(id_value(sub, st::ok, 0, 0), 0, now);
    default:
      break;
  }
  const std::uint16_t id = get_u16le(t.data, 0);
  auto it = s_.curves_ram.find(id);
  const bool exists = it != s_.curves_ram.end();
  switch (op) {
    case CurveOp::delete_one:
      s_.curves_ram.erase(id);
      if (xfer_.key == id) xfer_ = {};
      return finish(id_value(sub, st::ok, id, 0), 0, now);
    case CurveOp::add:
      s_.curves_ram[id] = Curve{Bytes(get_u16le(t.data, 2), 0), Bytes(get_u16le(t.data, 4), 0)};
      xfer_ = {};
      return finish(id_value(sub, st::ok, id, 0), 0, now);
    case CurveOp::read_sizes:
      // Undocumented: the client restarts a lost block read with "read sizes";
      // the simulator models that as resetting the curve's transfer cursor.
      if (xfer_.key == id) xfer_ = {};
      if (!exists) {
        if (o.missing_curve_zero_sizes) return finish(id_value(sub, st::ok, id, 0), 0, now);
        return finish(id_value(sub, o.missing_object_state, id, 0), 0, now);
      }
      return finish(id_value(sub, st::ok, id,
                             static_cast<std::uint32_t>(it->second.info.size() |
                                                        (it->second.data.size() << 16))),
                    0, now);
    default:
      break;
  }
  if (!exists) return finish(id_value(sub, o.missing_object_state, id, 0), 0, now);
  Curve& c = it->second;
  if (op == CurveOp::write_info || op == CurveOp::write_data) {
    const bool info = op == CurveOp::write_info;
    const auto state =
        block_write(info ? c.info : c.data, info ? XferKind::curve_info_w : XferKind::curve_data_w,
                    id, ByteView(t.data).subspan(2, 4));
    return finish(id_value(sub, state, id, 0), 0, now);
  }
  std::uint32_t v = 0;
  const bool info = op == CurveOp::read_info;
  const auto state = block_read(info ? c.info : c.data,
                                info ? XferKind::curve_info_r : XferKind::curve_data_r, id, v);
  return finish(id_value(sub, state, id, v), 0, now);
}

std::optional<Answer> Drive::on_command_table(const Telegram& t, std::int64_t now) {
  const std::uint8_t sub = codec::expected_answer_sub(t);
  const auto& o = s_.options;
  const auto op = static_cast<CtOp>(t.sub);
  if (op == CtOp::save_to_flash) {
    if (s_.mc_running) return finish(id_value(sub, o.flash_refused_state, 0, 0), 0, now);
    s_.ct_flash = s_.ct_ram;
    ++stats_.flash_saves;
    return finish_long(id_value(sub, st::ok, 0, 0), flash_save_duration_us(), now);
  }
  if (op == CtOp::delete_all) {
    s_.ct_ram.clear();
    xfer_ = {};
    return finish(id_value(sub, st::ok, 0, 0), 0, now);
  }
  const std::uint16_t key = get_u16le(t.data, 0);
  if (op == CtOp::defined_list) {
    if (key > 7) return finish(id_value(sub, o.missing_object_state, key, 0), 0, now);
    std::uint32_t bits = 0xFFFFFFFF;  // bit = 1: entry not defined
    for (unsigned i = 0; i < 32; ++i)
      if (s_.ct_ram.count(static_cast<std::uint16_t>(key * 32 + i))) bits &= ~(1u << i);
    return finish(id_value(sub, st::ok, key, bits), 0, now);
  }
  if (key > 255) return finish(id_value(sub, o.missing_object_state, key, 0), 0, now);
  auto it = s_.ct_ram.find(key);
  const bool exists = it != s_.ct_ram.end();
  switch (op) {
    case CtOp::delete_one:
      s_.ct_ram.erase(key);
      if (xfer_.key == key) xfer_ = {};
      return finish(id_value(sub, st::ok, key, 0), 0, now);
    case CtOp::setup_write: {
      const std::uint32_t size = get_u32le(t.data, 2);
      if (size > 0xFFFF) return finish(id_value(sub, s_.options.reject_state, key, 0), 0, now);
      s_.ct_ram[key] = Bytes(size, 0);
      xfer_ = Transfer{XferKind::ct_w, key, 0};
      return finish(id_value(sub, st::ok, key, 0), 0, now);
    }
    case CtOp::write_data: {
      if (!exists) return finish(id_value(sub, o.missing_object_state, key, 0), 0, now);
      const auto state =
          block_write(it->second, XferKind::ct_w, key, ByteView(t.data).subspan(2, 4));
      return finish(id_value(sub, state, key, 0), 0, now);
    }
    case CtOp::setup_read:
      if (!exists && o.missing_ct_entry_zero_size)
        return finish(id_value(sub, st::ok, key, 0), 0, now);  // size 0 for a missing entry
      if (!exists) return finish(id_value(sub, o.missing_object_state, key, 0), 0, now);
      xfer_ = Transfer{XferKind::ct_r, key, 0};
      return finish(id_value(sub, st::ok, key, static_cast<std::uint32_t>(it->second.size())), 0,
                    now);
    case CtOp::read_data: {
      if (!exists) return finish(id_value(sub, o.missing_object_state, key, 0), 0, now);
      std::uint32_t v = 0;
      const auto state = block_read(it->second, XferKind::ct_r, key, v);
      return finish(id_value(sub, state, key, v), 0, now);
    }
    default:
      break;
  }
  return error_answer(st::bad_sub_id, now);
}

}  // namespace lmcfg::sim
