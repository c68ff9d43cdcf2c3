// The line settings of a serial port, the same on every platform: names,
// validation against the LinRS rates, wire time per byte. Opening a port is
// serial.cpp (POSIX termios) or serial_win32.cpp (Win32 DCB).
#include <algorithm>
#include <string>

#include "transport/transport.hpp"

namespace lmcfg::transport {

namespace {

std::string allowed_bauds() {
  std::string s;
  for (const unsigned b : kSerialBaudRates) {
    if (!s.empty()) s += ", ";
    s += std::to_string(b);
  }
  return s;
}

}  // namespace

std::string_view parity_name(Parity p) noexcept {
  switch (p) {
    case Parity::none:
      return "none";
    case Parity::even:
      return "even";
    case Parity::odd:
      return "odd";
  }
  return "none";
}

std::optional<Parity> parity_from_name(std::string_view t) noexcept {
  if (t == "none" || t == "n" || t == "N") return Parity::none;
  if (t == "even" || t == "e" || t == "E") return Parity::even;
  if (t == "odd" || t == "o" || t == "O") return Parity::odd;
  return std::nullopt;
}

unsigned bits_per_byte(const SerialSettings& s) {
  return 1u + 8u + (s.parity == Parity::none ? 0u : 1u) + s.stop_bits;
}

Result<void> validate(const SerialSettings& s) {
  if (std::find(kSerialBaudRates.begin(), kSerialBaudRates.end(), s.baud) ==
      kSerialBaudRates.end()) {
    return Error(Errc::invalid_argument, "unsupported baud rate " + std::to_string(s.baud) +
                                             " (allowed: " + allowed_bauds() + ")");
  }
  if (s.parity != Parity::none && s.parity != Parity::even && s.parity != Parity::odd) {
    return Error(Errc::invalid_argument, "unsupported parity value " +
                                             std::to_string(static_cast<unsigned>(s.parity)) +
                                             " (allowed: none, even, odd)");
  }
  if (s.stop_bits != 1 && s.stop_bits != 2) {
    return Error(Errc::invalid_argument,
                 "unsupported stop bits " + std::to_string(s.stop_bits) + " (allowed: 1, 2)");
  }
  return {};
}

std::string format_settings(const SerialSettings& s) {
  const char p = s.parity == Parity::even ? 'E' : s.parity == Parity::odd ? 'O' : 'N';
  return std::to_string(s.baud) + " 8" + p + std::to_string(s.stop_bits);
}

Result<void> Transport::reconfigure(const SerialSettings&) {
  return Error(Errc::not_supported,
               describe() + ": the line settings of this link cannot be changed from here");
}

}  // namespace lmcfg::transport
