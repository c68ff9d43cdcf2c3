#include "codec/frame.hpp"

#include <cstdio>

namespace lmcfg::codec {

std::uint16_t checksum_add(ByteView bytes) {
  std::uint32_t sum = 0;
  for (auto b : bytes) sum += b;
  return static_cast<std::uint16_t>(sum & 0xFFFF);
}

std::uint16_t checksum_crc_ccitt(ByteView bytes, std::uint16_t init) {
  std::uint16_t crc = init;
  for (auto b : bytes) {
    crc = static_cast<std::uint16_t>(crc ^ (b << 8));
    for (int i = 0; i < 8; ++i) {
      crc = (crc & 0x8000) ? static_cast<std::uint16_t>((crc << 1) ^ 0x1021)
                           : static_cast<std::uint16_t>(crc << 1);
    }
  }
  return crc;
}

std::uint16_t checksum_crc_kermit(ByteView bytes) {
  std::uint16_t crc = 0x0000;
  for (auto b : bytes) {
    crc = static_cast<std::uint16_t>(crc ^ b);
    for (int i = 0; i < 8; ++i) {
      crc = (crc & 0x0001) ? static_cast<std::uint16_t>((crc >> 1) ^ 0x8408)
                           : static_cast<std::uint16_t>(crc >> 1);
    }
  }
  return crc;
}

namespace {

// Range of a frame (starting at the 01) that the checksum covers.
ByteView covered(const ChecksumConfig& cfg, ByteView frame_without_checksum) {
  switch (cfg.coverage) {
    case ChecksumCoverage::start_through_data:
      return frame_without_checksum;
    case ChecksumCoverage::id_through_data:
      return frame_without_checksum.subspan(1);
    case ChecksumCoverage::data_only:
      return frame_without_checksum.subspan(3);
  }
  return frame_without_checksum.subspan(1);
}

std::string fmt(const char* f, unsigned a, unsigned b = 0, unsigned c = 0) {
  char buf[160];
  std::snprintf(buf, sizeof buf, f, a, b, c);
  return buf;
}

}  // namespace

std::uint16_t compute_checksum(const ChecksumConfig& cfg, ByteView frame_without_checksum) {
  auto range = covered(cfg, frame_without_checksum);
  switch (cfg.mode) {
    case ChecksumMode::none:
      return 0;
    case ChecksumMode::add:
      return checksum_add(range);
    case ChecksumMode::crc_ccitt:
      return checksum_crc_ccitt(range, cfg.crc_init);
    case ChecksumMode::crc_kermit:
      return checksum_crc_kermit(range);
  }
  return 0;
}

Result<Bytes> encode(const Telegram& t, const ChecksumConfig& cfg) {
  const std::size_t len = t.data.size() + 3;
  if (len > kMaxLen) {
    return Error(Errc::invalid_argument,
                 fmt("telegram data of %u bytes exceeds LinRS LEN limit 63 (at most 60 data bytes)",
                     static_cast<unsigned>(t.data.size())));
  }
  Bytes out;
  out.reserve(len + 6);
  out.push_back(kStartHeader);
  out.push_back(t.id);
  out.push_back(static_cast<std::uint8_t>(len));
  out.push_back(kStartData);
  out.push_back(t.sub);
  out.push_back(t.main);
  out.insert(out.end(), t.data.begin(), t.data.end());
  if (cfg.mode != ChecksumMode::none) put_u16le(out, compute_checksum(cfg, out));
  out.push_back(kEndTelegram);
  return out;
}

Result<Telegram> decode(ByteView f, const ChecksumConfig& cfg) {
  const std::size_t chk = cfg.size();
  if (f.size() < 3) {
    return Error(Errc::frame_short,
                 fmt("telegram of %u bytes is too short to hold a header", unsigned(f.size())));
  }
  if (f[0] != kStartHeader) {
    return Error(Errc::frame_malformed, fmt("byte 0 is %02Xh, expected start header 01h", f[0]));
  }
  const std::size_t len = f[2];
  if (len < kMinLen || len > kMaxLen) {
    return Error(Errc::frame_malformed, fmt("LEN byte %02Xh is outside 03h..3Fh", unsigned(len)));
  }
  const std::size_t expected = 3 + len + chk + 1;
  if (f.size() < expected) {
    return Error(Errc::frame_short, fmt("telegram has %u bytes, LEN %02Xh requires %u",
                                        unsigned(f.size()), unsigned(len), unsigned(expected)));
  }
  if (f.size() > expected) {
    return Error(Errc::frame_overlong, fmt("telegram has %u bytes, LEN %02Xh requires %u",
                                           unsigned(f.size()), unsigned(len), unsigned(expected)));
  }
  if (f[3] != kStartData) {
    return Error(Errc::frame_malformed, fmt("byte 3 is %02Xh, expected start data 02h", f[3]));
  }
  if (f[expected - 1] != kEndTelegram) {
    return Error(Errc::frame_malformed, fmt("byte %u is %02Xh, expected end of telegram 04h",
                                            unsigned(expected - 1), f[expected - 1]));
  }
  if (chk != 0) {
    const std::uint16_t want = compute_checksum(cfg, f.first(3 + len));
    const std::uint16_t got = get_u16le(f, 3 + len);
    if (want != got) {
      return Error(Errc::checksum_mismatch,
                   fmt("checksum %04Xh received, %04Xh computed", got, want));
    }
  }
  Telegram t;
  t.id = f[1];
  t.sub = f[4];
  t.main = f[5];
  t.data.assign(f.begin() + 6, f.begin() + static_cast<std::ptrdiff_t>(3 + len));
  return t;
}

void StreamDecoder::feed(ByteView bytes) {
  compact();
  buf_.insert(buf_.end(), bytes.begin(), bytes.end());
}

void StreamDecoder::compact() {
  if (pos_ > 0 && (pos_ >= 4096 || pos_ == buf_.size())) {
    buf_.erase(buf_.begin(), buf_.begin() + static_cast<std::ptrdiff_t>(pos_));
    pos_ = 0;
  }
}

void StreamDecoder::reset() {
  buf_.clear();
  pos_ = 0;
}

std::optional<Result<Telegram>> StreamDecoder::next() {
  const std::size_t avail = buf_.size() - pos_;
  if (avail == 0) return std::nullopt;
  ByteView view(buf_.data() + pos_, avail);

  // Garbage before a start header: skip it and say so.
  if (view[0] != kStartHeader) {
    std::size_t skip = 0;
    while (skip < view.size() && view[skip] != kStartHeader) ++skip;
    pos_ += skip;
    garbage_ += skip;
    return Result<Telegram>(
        Error(Errc::frame_malformed,
              fmt("skipped %u byte(s) of garbage before a start header 01h", unsigned(skip))));
  }
  if (view.size() < 4) return std::nullopt;
  const std::size_t len = view[2];
  // A start byte whose header cannot begin a telegram: drop that one byte and
  // hunt for the next 01, so a real telegram following it is not lost.
  auto drop_start = [&](Errc code, std::string why) {
    pos_ += 1;
    garbage_ += 1;
    return std::optional<Result<Telegram>>(Error(code, std::move(why)));
  };
  if (len < kMinLen || len > kMaxLen) {
    return drop_start(Errc::frame_malformed,
                      fmt("LEN byte %02Xh is outside 03h..3Fh; resynchronising", unsigned(len)));
  }
  if (view[3] != kStartData) {
    return drop_start(Errc::frame_malformed,
                      fmt("byte 3 is %02Xh, expected start data 02h; resynchronising", view[3]));
  }
  const std::size_t total = 3 + len + cfg_.size() + 1;
  if (view.size() < total) return std::nullopt;
  if (view[total - 1] != kEndTelegram) {
    // Either bytes were lost (the drive frames by LEN, so a short telegram
    // swallows the next bytes) or a byte was inserted.
    return drop_start(
        Errc::frame_short,
        fmt("no end of telegram 04h where LEN %02Xh puts it (found %02Xh); resynchronising",
            unsigned(len), view[total - 1]));
  }
  auto r = decode(view.first(total), cfg_);
  if (!r.ok()) {
    if (r.error().code == make_error_code(Errc::checksum_mismatch)) {
      pos_ += total;  // framing was intact: the whole telegram is consumed
      return r;
    }
    pos_ += 1;
    garbage_ += 1;
    return r;
  }
  pos_ += total;
  return r;
}

std::optional<Error> StreamDecoder::flush_idle() {
  const std::size_t avail = buf_.size() - pos_;
  if (avail == 0) return std::nullopt;
  ByteView view(buf_.data() + pos_, avail);
  std::string msg;
  if (view[0] == kStartHeader && view.size() >= 3) {
    const std::size_t total = 3 + view[2] + cfg_.size() + 1;
    msg = fmt("line went idle after %u byte(s) of a telegram whose LEN %02Xh requires %u",
              unsigned(avail), view[2], unsigned(total));
  } else {
    msg = fmt("line went idle after %u byte(s) of an incomplete telegram", unsigned(avail));
  }
  garbage_ += avail;
  reset();
  return Error(Errc::frame_short, std::move(msg));
}

}  // namespace lmcfg::codec
