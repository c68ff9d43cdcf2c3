#pragma once
// The drive client over LinUDP V2's configuration (RTC) channel: the same
// interface as LinrsClient (client.hpp), so every operation runs unchanged.
// Each rule cites its source (docs/references.md: LinUDP V2, LinUDP DLL, C1250 notes);
// docs/linudp.md lists the choices and what only a real drive can confirm.
//
// Contract (safety on a shared network, LinUDP V2 §4.4, §7):
// - Only the RTC part is ever sent (request definition 04h, response 1FFh):
//   never a control word, never an MC command, so nothing moves an axis.
// - One command in flight. Each command takes a new count (2..14, never the
//   drive's last echo); a resend repeats the same bytes with the same count,
//   which the drive does not execute again (LinUDP V2 §7), so lost datagrams are
//   resent for writes as well as reads.
// - The first exchange of a session is a NOP (00h): it learns the drive's
//   count, so no later command can carry the count the drive already holds.
// - A reply counts only when its echo equals the count sent; other echoes
//   (stale replies, C1250 notes) are ignored. Status 02h/05h: still running,
//   polled by resending. Any other status is final; 00h (and 04h inside block
//   transfers) is success, the rest a refusal (Errc::drive_refused) naming the
//   command, its subject and the status of LinUDP V2 p14.
// - Flash saves (40h, 80h) are never resent while they may run (C1250 notes:
//   a resend restarts the save). Unacknowledged (field reports), the same datagram
//   (same count) goes once more when no save can still run (90 s after it,
//   C1250 notes): a drive that had it does not save again (LinUDP V2 §7), one whose
//   request was lost saves now. Still no answer: ops::long_step's find_again().
// - An all-zero datagram means another master holds the drive (C1250 notes):
//   Errc::io_error with held_by_other_master_message().
#include <memory>
#include <optional>
#include <string>

#include "client/client.hpp"
#include "linudp/codec.hpp"

namespace lmcfg::client {

// The C1250 notes' client makes at most 6 retries of a lost exchange.
inline constexpr int kLinudpAttempts = 7;

// The message for a drive that answers with all-zero telegrams.
std::string held_by_other_master_message(const std::string& where);

class LinudpClient final : public Client {
 public:
  LinudpClient(transport::Transport& link, ClientOptions opt);

  Capabilities capabilities() const override;
  transport::Transport& link() override { return link_; }

  Result<codec::DefaultResponse> default_response(
      codec::ResponseRequest kind = codec::ResponseRequest::default_response) override;
  Result<std::uint32_t> read_ram(std::uint16_t upid) override;
  Result<void> write_ram(std::uint16_t upid, std::uint32_t value) override;
  Result<void> write_ram_rom(std::uint16_t upid, std::uint32_t value) override;
  Result<std::uint32_t> read_rom(std::uint16_t upid) override;
  Result<void> write_rom(std::uint16_t upid, std::uint32_t value) override;
  Result<void> write_rom_confirmed(std::uint16_t upid, std::uint32_t value) override;
  Result<std::uint16_t> get_type(std::uint16_t upid) override;
  Result<std::uint32_t> get_min(std::uint16_t upid) override;
  Result<std::uint32_t> get_max(std::uint16_t upid) override;
  Result<std::uint32_t> get_default(std::uint16_t upid) override;
  Result<std::optional<std::uint16_t>> read_address_usage(std::uint16_t upid) override;
  Result<std::vector<ModifiedParam>> modified_list(int layer) override;
  Result<std::vector<UpidInfo>> upid_list(
      int layer, const std::function<void(std::size_t)>& progress = {}) override;
  Result<void> default_layer(int layer) override;
  Result<Millis> find_again(const std::string& what) override;
  Result<std::optional<CurveSizes>> curve_sizes(std::uint16_t curve) override;
  Result<Bytes> read_curve_info(std::uint16_t curve, std::uint16_t size) override;
  Result<Bytes> read_curve_data(std::uint16_t curve, std::uint16_t size) override;
  Result<std::optional<CurveBlocks>> read_curve(std::uint16_t curve) override;
  Result<void> write_curve(std::uint16_t curve, ByteView info, ByteView data) override;
  Result<void> delete_curve(std::uint16_t curve) override;
  Result<void> delete_all_curves() override;
  Result<void> save_curves() override;
  Result<std::vector<std::uint16_t>> ct_defined_entries() override;
  Result<Bytes> read_ct_entry(std::uint16_t entry) override;
  Result<void> write_ct_entry(std::uint16_t entry, ByteView bytes) override;
  Result<void> delete_ct_entry(std::uint16_t entry) override;
  Result<void> delete_all_ct() override;
  Result<void> save_ct() override;
  Result<std::optional<Bytes>> probe_ct_entry(std::uint16_t entry) override;
  Result<void> stop_mc() override;
  Result<void> start_mc() override;
  Result<void> reset() override;
  Result<void> reset(Millis timeout) override;
  Result<std::string> actual_error_text() override;
  Result<std::string> error_text(std::uint16_t code) override;
  Result<codec::ErrorCounters> error_counters() override;
  Result<codec::ErrorLogEntry> error_log_entry(std::uint16_t index) override;

  // One command (LinUDP V2 §7): the RTC reply with its final status, or the
  // error. Public for tests of the count rule.
  enum class Kind : std::uint8_t {
    ordinary,  // resent after `timeout` without a reply, up to kLinudpAttempts
    long_op,   // 30h-36h: resent every second, up to `timeout` in all
    once,      // 40h, 80h, 30h: sent once, `timeout` waited
  };
  struct Reply {
    linudp::RtcBlock rtc;
    linudp::Response response;
  };
  Result<Reply> command(linudp::RtcBlock req, Kind kind, Millis timeout,
                        const std::string& subject = {});
  // A scan's probe (lmcfg scan, link/linudp_scan.hpp): the session's first
  // exchange, a NOP (LinUDP V2 §7: it runs nothing whichever count the drive
  // holds), sent at most `attempts` times (the same count, §7) and
  // waited `deadline` each. The reply, Errc::timeout, or Errc::io_error with
  // held_by_other_master_message().
  Result<Reply> probe(Millis deadline, int attempts);
  // The count the drive echoed last (nullopt before the first reply).
  std::optional<std::uint8_t> last_echo() const { return last_echo_; }

 private:
  Result<void> seed();
  // One datagram received while `count` is in flight: the reply (02h/05h
  // included), nothing (ignored: garbled, no RTC part, another count), or
  // the error of a drive held by another master.
  Result<std::optional<Reply>> match(const Bytes& got, std::uint8_t count);
  Error no_answer(const std::string& what, std::uint8_t count, int sent,
                  std::int64_t waited_ns) const;
  Result<Reply> simple(linudp::Cmd id, std::uint16_t w2 = 0, std::uint32_t value = 0,
                       const std::string& subject = {});
  Result<void> expect_ok(const Reply& r, std::uint8_t id, const std::string& subject,
                         bool block = false) const;
  Error refused(std::uint8_t id, const std::string& subject, std::uint8_t st) const;
  Result<std::uint32_t> read_value(linudp::Cmd id, std::uint16_t upid);
  Result<void> write_value(linudp::Cmd id, std::uint16_t upid, std::uint32_t value);
  // Reads `size` bytes in 4-byte chunks with `chunk` after `setup` (LinUDP V2
  // p13-p19; open there: the 00h may come with the last chunk or on one more read).
  Result<Bytes> read_chunks(linudp::RtcBlock setup, linudp::Cmd chunk, std::uint16_t key,
                            std::size_t size, const std::string& subject);
  Result<void> write_chunks(linudp::Cmd chunk, std::uint16_t key, ByteView bytes,
                            const std::string& subject);
  Result<void> long_command(linudp::Cmd id, Kind kind, Millis timeout, const std::string& what);
  // A flash save (40h, 80h) sent at `start` and not acknowledged: once no
  // save can still run, the same datagram again, with its count (LinUDP V2 §7:
  // not carried out again if the drive had it; carried out if it was lost).
  Result<Reply> resend_save(linudp::Cmd id, const std::string& what, std::int64_t start,
                            Error silence);
  template <class F>
  Result<std::vector<std::uint16_t>> walk_list(linudp::Cmd start, linudp::Cmd next, int layer,
                                               F&& on_item);
  std::string where() const { return link_.describe(); }

  transport::Transport& link_;
  int attempts_ = kLinudpAttempts;  // of an ordinary command (probe(): fewer)
  // Set: command() sends with this count (resend_save), not a new one.
  std::optional<std::uint8_t> resend_count_;
  linudp::Counter counter_;
  std::optional<std::uint8_t> last_echo_;
  bool seeded_ = false;
  // The last command was one after which drives fall silent (C1250 notes):
  // an unanswered next command is resent for up to recover_timeout.
  bool quiet_expected_ = false;
  std::string quiet_after_;
};

}  // namespace lmcfg::client
