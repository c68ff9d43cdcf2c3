#include "devicenet/messages.hpp"

#include <algorithm>

namespace lmcfg::devicenet {

std::uint16_t group2_id(std::uint8_t mac, Group2 message) {
  return static_cast<std::uint16_t>(0x400 | ((mac & 0x3F) << 3) |
                                    static_cast<std::uint8_t>(message));
}

std::uint16_t group1_id(std::uint8_t message, std::uint8_t mac) {
  return static_cast<std::uint16_t>(((message & 0x0F) << 6) | (mac & 0x3F));
}

std::string describe_identifier(std::uint32_t id) {
  static constexpr const char* kGroup2[8] = {"master's I/O bit-strobe command",
                                             "master's I/O multicast poll",
                                             "master's change of state acknowledge",
                                             "slave's explicit/unconnected response",
                                             "master's explicit request",
                                             "master's I/O poll command",
                                             "unconnected explicit request",
                                             "duplicate MAC ID check"};
  if (id > 0x7FF) return "not a DeviceNet identifier";
  if (id < 0x400) {
    const auto msg = static_cast<std::uint8_t>(id >> 6);
    const char* what = msg == kSlavePollResponse        ? "slave's I/O poll response"
                       : msg == kSlaveBitStrobeResponse ? "slave's I/O bit-strobe response"
                       : msg == kSlaveCosMessage        ? "slave's I/O change of state"
                                                        : "group 1 message";
    return "Group 1 MAC " + hex(id & 0x3F, 2, "h") + " " + what + " (" + hex(msg, 1, "h") + ")";
  }
  if (id < 0x600) return "Group 2 MAC " + hex((id >> 3) & 0x3F, 2, "h") + " " + kGroup2[id & 7];
  if (id < 0x7C0) return "Group 3 MAC " + hex(id & 0x3F, 2, "h");
  return "Group 4";
}

Bytes Explicit::encode() const {
  Bytes out(2 + data.size());
  out[0] = static_cast<std::uint8_t>((fragmented ? 0x80 : 0) | (xid ? 0x40 : 0) | (mac & 0x3F));
  out[1] = static_cast<std::uint8_t>((response ? 0x80 : 0) | (service & 0x7F));
  std::copy(data.begin(), data.end(), out.begin() + 2);
  return out;
}

Result<Explicit> Explicit::decode(ByteView body) {
  if (body.size() < 2) {
    return Error(Errc::frame_short, "explicit message of " + std::to_string(body.size()) +
                                        " byte(s): header and service need 2");
  }
  Explicit e;
  e.fragmented = (body[0] & 0x80) != 0;
  e.xid = (body[0] & 0x40) != 0;
  e.mac = body[0] & 0x3F;
  e.response = (body[1] & 0x80) != 0;
  e.service = body[1] & 0x7F;
  e.data.assign(body.begin() + 2, body.end());
  return e;
}

Explicit allocate(std::uint8_t master_mac, std::uint8_t choice) {
  return Explicit{false, false,     master_mac,
                  false, kAllocate, Bytes{kDeviceNetClass, 0x01, choice, master_mac}};
}

Explicit release(std::uint8_t master_mac, std::uint8_t choice) {
  return Explicit{false, false, master_mac, false, kRelease, Bytes{kDeviceNetClass, 0x01, choice}};
}

Explicit get_attribute(std::uint8_t master_mac, std::uint8_t cls, std::uint8_t instance,
                       std::uint8_t attribute) {
  return Explicit{
      false, false, master_mac, false, kGetAttributeSingle, Bytes{cls, instance, attribute}};
}

Explicit set_attribute(std::uint8_t master_mac, std::uint8_t cls, std::uint8_t instance,
                       std::uint8_t attribute, ByteView value) {
  Bytes data(3 + value.size());
  data[0] = cls;
  data[1] = instance;
  data[2] = attribute;
  std::copy(value.begin(), value.end(), data.begin() + 3);
  return Explicit{false, false, master_mac, false, kSetAttributeSingle, std::move(data)};
}

std::string_view service_name(std::uint8_t service) {
  switch (service) {
    case kGetAttributeSingle:
      return "Get_Attribute_Single";
    case kSetAttributeSingle:
      return "Set_Attribute_Single";
    case kErrorResponse:
      return "Error Response";
    case kAllocate:
      return "Allocate_Master/Slave_Connection_Set";
    case kRelease:
      return "Release_Master/Slave_Connection_Set";
  }
  return "service";
}

std::string_view general_error_text(std::uint8_t code) {
  switch (code) {  // CIP general status codes
    case 0x02:
      return "resource unavailable";
    case 0x08:
      return "service not supported";
    case 0x09:
      return "invalid attribute value";
    case 0x0B:
      return "already in requested mode/state";
    case 0x0C:
      return "object state conflict";
    case 0x0E:
      return "attribute not settable";
    case 0x10:
      return "device state conflict";
    case 0x13:
      return "not enough data";
    case 0x14:
      return "attribute not supported";
    case 0x15:
      return "too much data";
    case 0x16:
      return "object does not exist";
    case 0x20:
      return "invalid parameter";
  }
  return {};
}

Result<Bytes> response_data(const Explicit& request, const Explicit& response) {
  const std::string what =
      std::string(service_name(request.service)) + " " + hex(request.service, 2, "h");
  if (!response.response) {
    return Error(Errc::unexpected_response, "a request (service " + hex(response.service, 2, "h") +
                                                ") instead of the response to " + what);
  }
  if (response.service == kErrorResponse) {
    const std::uint8_t general = response.data.size() > 0 ? response.data[0] : 0;
    const std::uint8_t additional = response.data.size() > 1 ? response.data[1] : 0xFF;
    std::string text = "error response to " + what + ": general error " + hex(general, 2, "h");
    if (auto t = general_error_text(general); !t.empty()) text += " " + std::string(t);
    text += ", additional " + hex(additional, 2, "h");
    return Error(Errc::drive_refused, text);
  }
  if (response.service != request.service) {
    return Error(Errc::unexpected_response,
                 "response to service " + hex(response.service, 2, "h") + " instead of " + what);
  }
  return response.data;
}

std::vector<Bytes> fragment_io(ByteView data) {
  if (data.size() <= 8) return {Bytes(data.begin(), data.end())};
  std::vector<Bytes> frames;
  for (std::size_t at = 0, count = 0; at < data.size(); at += 7, ++count) {
    const std::size_t n = std::min<std::size_t>(7, data.size() - at);
    const std::uint8_t type = at == 0 ? 0x00 : (at + n == data.size() ? 0x80 : 0x40);
    Bytes f{static_cast<std::uint8_t>(type | (count & 0x3F))};
    f.insert(f.end(), data.begin() + static_cast<std::ptrdiff_t>(at),
             data.begin() + static_cast<std::ptrdiff_t>(at + n));
    frames.push_back(std::move(f));
  }
  return frames;
}

Result<std::optional<Bytes>> IoReassembler::feed(ByteView frame, bool fragmented) {
  if (!fragmented) {
    next_count_ = -1;
    partial_.clear();
    return std::optional<Bytes>(Bytes(frame.begin(), frame.end()));
  }
  if (frame.empty()) return Error(Errc::frame_short, "I/O fragment without its protocol byte");
  const std::uint8_t type = frame[0] & 0xC0;
  const int count = frame[0] & 0x3F;
  if (type == 0x00) {  // first: starts over whatever was pending
    partial_.assign(frame.begin() + 1, frame.end());
    next_count_ = (count + 1) & 0x3F;
    return std::optional<Bytes>();
  }
  if (next_count_ < 0 || count != next_count_) {
    const std::string expected =
        next_count_ < 0 ? std::string("a first fragment") : "count " + std::to_string(next_count_);
    next_count_ = -1;
    partial_.clear();
    return Error(Errc::frame_malformed, "I/O fragment count " + std::to_string(count) +
                                            " out of sequence (expected " + expected + ")");
  }
  partial_.insert(partial_.end(), frame.begin() + 1, frame.end());
  next_count_ = (count + 1) & 0x3F;
  if (type == 0x80) {
    next_count_ = -1;
    return std::optional<Bytes>(std::move(partial_));
  }
  return std::optional<Bytes>();
}

}  // namespace lmcfg::devicenet
