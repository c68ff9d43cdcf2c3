#pragma once
// sim::LinudpDrive: the simulated drive (sim::Drive, its DriveState and its
// LinRS logic) answering LinUDP V2's configuration channel. Each RTC command
// (LinUDP V2 p13-p19) is carried out as the LinRS request of the same
// function (LinRS §9-§14) on the same sim::Drive, so a drive simulated
// over LinUDP holds exactly what the LinRS simulator holds; the LinUDP layer
// adds the count rule (LinUDP V2 §7), the reply layout (§4.4.2), the status
// codes (p14) and the field behaviours (C1250 notes, field reports) and the
// points LinUDP V2 leaves open as options.
// No clock of its own: datagrams in with their arrival time, answers out
// with their delay (as sim::Drive).
#include <cstdint>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <vector>

#include "linudp/codec.hpp"
#include "sim/drive.hpp"

namespace lmcfg::sim {

// The field behaviours (C1250 notes, field reports) and both readings of the
// points LinUDP V2 leaves open, which the client must cope with. Defaults:
// the manual's reading.
struct LinudpField {
  // C1250 notes (open in LinUDP V2): a flash save (40h, 80h) is never acknowledged; the
  // drive is deaf while it runs (DriveState::timing.flash_save_us).
  bool unacknowledged_saves = false;
  // The duration of a flash save (field reports: 39-75 s); 0 keeps the
  // state's Timing::flash_save_us.
  std::int64_t save_us = 0;
  // C1250 notes: after a ROM write (12h, 14h) the drive is silent this long.
  std::int64_t silent_after_rom_write_us = 0;
  // C1250 notes: every Nth reply is preceded by a copy of the previous reply
  // (a stale echo, old count). 0: never.
  unsigned stale_echo_every = 0;
  // Lost datagrams: every Nth request / every Nth reply is dropped. 0: none.
  unsigned lose_request_every = 0;
  unsigned lose_reply_every = 0;
  // C1250 notes: another master holds the drive: every reply is 64 zero bytes.
  bool held_by_other_master = false;
  // Open (C1250 notes vs LinUDP DLL): curve and CT reads (60h-62h, 85h-8Eh)
  // refused with D1h while MC runs.
  bool table_reads_need_mc_stopped = false;
  // Open in LinUDP V2: true = the last chunk of a block read comes with 04h and 00h
  // on one more read (the DLL's reading); false = 00h with the last data (LinRS's).
  bool end_on_extra_read = false;
  // Open in LinUDP V2: true = a list started at a layer's base runs on through the
  // later layers (the DLL's reading); false = C6h at the end of the layer.
  bool list_spans_layers = false;
  // Open in LinUDP V2: the 60h reply carries the info/data sizes in w3/w4.
  bool curve_start_gives_sizes = true;
  // Open in LinUDP V2: what a resend gets while a long command runs: 02h, 05h, or
  // 0 = no reply at all.
  std::uint8_t running_status = linudp::status::running;
  // Open in LinUDP V2 §7: counts 1 and 15 (and 0 outside a restart) are ignored.
  bool strict_counts = false;
  // Open (a C1250 notes claim): datagrams from a source port other than 41136 are ignored
  // (only where the port is known: the UDP server).
  bool filter_source_port = false;
  // A lost flash-save datagram (C1250 notes and LinUDP V2 §7 decide what a resend
  // does): the first N save requests (40h, 80h with a new count; not their
  // resends with the same count) are lost,
  // or the replies to the first N saves (the save runs; a resend with its
  // count gets the reply, LinUDP V2 §7).
  unsigned lose_save_requests = 0;
  unsigned lose_save_replies = 0;
  // A connection cut: after this many writing commands (restore, default)
  // the drive answers nothing more (0: never).
  unsigned silent_after_writes = 0;
  friend bool operator==(const LinudpField&, const LinudpField&) = default;
};
// "name=value" (or "name" for true) onto `f`; the names are the fields'
// (unacknowledged_saves, silent_after_rom_write_s, ...); Errc::invalid_argument
// naming the unknown name or bad value. field_names(): every name, for --help.
Result<void> set_field(LinudpField& f, std::string_view spec);
std::string field_names();
// The options that differ from the defaults, as "name=value" words.
std::vector<std::string> field_words(const LinudpField& f);

struct LinudpStats {
  std::uint64_t datagrams = 0;
  std::uint64_t commands = 0;          // executed (a new count)
  std::uint64_t resends = 0;           // same count again: answered from the cache
  std::uint64_t motion_telegrams = 0;  // with a control word or MC part (lmcfg sends none)
  std::uint64_t ignored = 0;           // lost, deaf, filtered, strict counts
  std::uint64_t counts_seen_15 = 0;    // counts outside 2..14 (not a restart's 0)
  std::uint64_t saves = 0;             // flash saves (40h, 80h) carried out
};

class LinudpDrive {
 public:
  explicit LinudpDrive(std::shared_ptr<Drive> drive, LinudpField field = {});

  // One datagram that arrived at `now_ns` from `source_port` (0: unknown).
  std::vector<Answer> receive(ByteView datagram, std::int64_t now_ns,
                              std::uint16_t source_port = 0);

  Drive& drive() { return *drive_; }
  std::shared_ptr<Drive> shared_drive() const { return drive_; }
  LinudpField& field() { return field_; }
  const LinudpStats& stats() const { return stats_; }

 private:
  struct Outcome {
    linudp::RtcBlock reply;
    std::int64_t duration_ns = 0;  // a long command: its reply is ready after this
    bool unanswered = false;       // a save never acknowledged (field reports)
  };
  Outcome execute(const linudp::RtcBlock& rtc, std::int64_t now_ns);
  // The LinRS request for `rtc`, nullopt for commands the layer answers itself.
  std::optional<codec::Telegram> linrs_request(const linudp::RtcBlock& rtc) const;
  Outcome from_linrs(const linudp::RtcBlock& rtc, const std::optional<Answer>& a,
                     std::int64_t now_ns);
  // The reply words and status from the LinRS answer of an accepted request.
  void fill(const linudp::RtcBlock& rtc, const codec::Telegram& answer, Outcome& o);
  Outcome list_next(const linudp::RtcBlock& rtc, bool modified, std::int64_t now_ns);
  Bytes reply_bytes(const linudp::Request& req, const linudp::RtcBlock& rtc) const;

  std::shared_ptr<Drive> drive_;
  LinudpField field_;
  LinudpStats stats_;
  std::optional<std::uint8_t> last_count_;
  std::optional<linudp::RtcBlock> cached_;  // final reply of the last count
  std::int64_t ready_at_ns_ = 0;            // when the cached reply is final
  bool cached_unanswered_ = false;
  std::int64_t deaf_until_ns_ = 0;
  Bytes previous_reply_;
  std::uint64_t requests_seen_ = 0, replies_made_ = 0, writes_ = 0;
  unsigned save_requests_lost_ = 0, save_replies_lost_ = 0;
  int lost_save_count_ = -1;  // the count of the save request lost last
  // Lists (the "spans layers" reading): the layer the LinRS list is in.
  int list_layer_ = 0;
  bool list_modified_ = false;
  bool list_ended_ = false;            // the LinRS list answered C6
  std::set<std::uint16_t> list_seen_;  // UPIDs listed since the start
  // Block reads (the "extra read" reading): the chunk command owing its 00h.
  std::optional<std::uint8_t> owed_end_;
};

}  // namespace lmcfg::sim
