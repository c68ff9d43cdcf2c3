#pragma once
// DeviceNet messages of the Predefined Master/Slave Connection Set as pure
// code: CAN identifiers of Group 1 and Group 2, explicit request/response
// bodies (Allocate, Release, Get/Set_Attribute_Single, error responses) and
// the fragmentation of I/O data longer than 8 bytes. Seed 000 does not
// describe this layer (it is the DeviceNet specification's); the golden
// vectors in tests/devicenet/test_messages.cpp come from vendors' published
// DeviceNet manuals, cited there. docs/can.md.
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "common/bytes.hpp"
#include "common/result.hpp"

namespace lmcfg::devicenet {

// Group 2 message IDs (identifier bits 2..0; bits 8..3 the MAC ID, bits 10..9 = 10b).
enum class Group2 : std::uint8_t {
  master_bit_strobe = 0,  // source MAC = master
  master_multicast_poll = 1,
  master_cos_ack = 2,                // destination MAC
  slave_explicit_response = 3,       // source MAC = slave
  master_explicit_request = 4,       // destination MAC = slave
  master_io_poll = 5,                // destination MAC = slave
  unconnected_explicit_request = 6,  // destination MAC = slave (Allocate, Release)
  duplicate_mac_check = 7,           // source MAC
};
// Group 1 message IDs (identifier bits 9..6; bits 5..0 the source MAC).
inline constexpr std::uint8_t kSlaveCosMessage = 0xD;
inline constexpr std::uint8_t kSlaveBitStrobeResponse = 0xE;
inline constexpr std::uint8_t kSlavePollResponse = 0xF;

std::uint16_t group2_id(std::uint8_t mac, Group2 message);
std::uint16_t group1_id(std::uint8_t message, std::uint8_t mac);
// "Group 2 MAC 09h master's explicit request", "Group 1 MAC 09h slave's I/O
// poll response", "Group 3 ..."; for traces.
std::string describe_identifier(std::uint32_t id);

// Services (CIP) used on the DeviceNet object (class 3) and connections (class 5).
inline constexpr std::uint8_t kGetAttributeSingle = 0x0E;
inline constexpr std::uint8_t kSetAttributeSingle = 0x10;
inline constexpr std::uint8_t kErrorResponse = 0x14;
inline constexpr std::uint8_t kAllocate = 0x4B;
inline constexpr std::uint8_t kRelease = 0x4C;
inline constexpr std::uint8_t kDeviceNetClass = 0x03;
inline constexpr std::uint8_t kConnectionClass = 0x05;
inline constexpr std::uint8_t kPolledConnection = 0x02;        // Connection instance 2
inline constexpr std::uint8_t kExpectedPacketRate = 0x09;      // Connection attribute 9 (UINT, ms)
inline constexpr std::uint8_t kProducedConnectionSize = 0x07;  // attribute 7 (UINT, bytes)
inline constexpr std::uint8_t kConsumedConnectionSize = 0x08;  // attribute 8 (UINT, bytes)

// Allocation choice bits.
inline constexpr std::uint8_t kAllocExplicit = 0x01;
inline constexpr std::uint8_t kAllocPolled = 0x02;
inline constexpr std::uint8_t kAllocBitStrobe = 0x04;

// One non-fragmented explicit message body: header (Frag, XID, MAC), service
// with the R/R bit, then the service data (class, instance, attribute, data
// for requests; response data for responses).
struct Explicit {
  bool fragmented = false;
  bool xid = false;
  std::uint8_t mac = 0;  // the other end's MAC ID (requests: the master's)
  bool response = false;
  std::uint8_t service = 0;  // without the R/R bit
  Bytes data;

  Bytes encode() const;  // at most 8 bytes for a non-fragmented message
  static Result<Explicit> decode(ByteView body);
};

Explicit allocate(std::uint8_t master_mac, std::uint8_t choice);
Explicit release(std::uint8_t master_mac, std::uint8_t choice);
Explicit get_attribute(std::uint8_t master_mac, std::uint8_t cls, std::uint8_t instance,
                       std::uint8_t attribute);
Explicit set_attribute(std::uint8_t master_mac, std::uint8_t cls, std::uint8_t instance,
                       std::uint8_t attribute, ByteView value);

// A response to `request` as a result: the response's data, or Errc::drive_refused
// naming the general and additional error codes ("error response to
// Allocate: general error 0Ch object state conflict, additional 01h"), or
// Errc::unexpected_response for another service.
Result<Bytes> response_data(const Explicit& request, const Explicit& response);
std::string_view general_error_text(std::uint8_t code);  // "" when unknown
std::string_view service_name(std::uint8_t service);     // "Allocate", ...

// I/O data over several frames (longer than 8 bytes): each frame starts with
// the fragmentation protocol byte, type in bits 7..6 (00b first, 01b middle,
// 10b last) and a count in bits 5..0, followed by up to 7 data bytes.
// Data of 8 bytes or less is one frame without that byte.
std::vector<Bytes> fragment_io(ByteView data);

class IoReassembler {
 public:
  // nullopt while a fragmented message is incomplete; the data when complete.
  // A fragment out of sequence drops the partial message (Errc::frame_malformed
  // naming the expected and received counts).
  Result<std::optional<Bytes>> feed(ByteView frame, bool fragmented);

 private:
  Bytes partial_;
  int next_count_ = -1;  // -1: waiting for a first fragment
};

}  // namespace lmcfg::devicenet
