#pragma once
// Drive client: request/response over a Transport, per-request deadlines,
// bounded retries for idempotent reads only, and every operation of the LinRS
// message groups (LinRS §6-14) as a typed call.
//
// Contract:
// - One request is in flight at a time; answers from other MACIDs are ignored.
// - A read that times out or arrives garbled is repeated (discarding input) at
//   most `read_retries` times. A write is never repeated blindly: it fails with
//   the link error and the caller re-reads state before deciding. write_rom_confirmed
//   does that re-read itself: after a lost answer it reads the ROM value back
//   and succeeds only if the drive holds the value written.
// - After a lost or garbled answer the client lets the line settle (reads and
//   drops everything until it has been quiet for `settle`) before it sends the
//   next request, so a late answer is never taken for the next request's.
//   Answers that cannot belong to the request in flight (other MACID, other
//   sub ID, other UPID / curve / entry key) are ignored, not accepted.
// - Block writes check the drive's state per chunk (04h more, 00h done): a
//   drive that lost the transfer (reset) makes the write fail, never succeed.
// - Block transfers (curve info/data, command table entries) are restarted from
//   their setup telegram when a chunk is lost, never resumed mid-block.
// - A drive's error communication state (C1..C9) becomes an Error whose code is
//   in comm_state_category(), with the state's meaning in the message.
#include <atomic>
#include <cstdint>
#include <functional>
#include <optional>
#include <vector>

#include "codec/frame.hpp"
#include "codec/messages.hpp"
#include "codec/requests.hpp"
#include "transport/transport.hpp"

namespace lmcfg::client {

using transport::Millis;

struct ClientOptions {
  std::uint8_t id = 0x11;  // LinRS §15 factory MACID parameter value
  codec::ChecksumConfig checksum;
  codec::DefaultResponseLayout layout;
  // Answer deadline of an ordinary request (drive answers in 0.5-1.5 ms,
  // §6.1.1.1). With `adaptive_deadline` it is the upper bound (and the
  // deadline until the first answer has been timed); without, the deadline.
  Millis timeout{200};
  // ---- adaptive answer deadline (docs/reliability.md), like TCP's RTO ----
  // true: an ordinary read (not a write, whose late answer would count as
  // lost and which is never resent; not a long operation) waits
  //   wire(request) + wire(longest answer its group can have) + max(turnaround_max
  //   + the link's receive latency, srtt + 4 x rttvar) + deadline_margin,
  // where srtt/rttvar smooth the measured round trip minus its wire time
  // (Jacobson/Karels, first attempts only: Karn's rule), at most `timeout`;
  // `timeout` itself until the first answer has been timed. A timeout doubles
  // the deadline for the next attempts (backoff) until an answer is timed
  // again; bytes that arrive late (while settling) count as a round trip. On a
  // link without a byte time (TCP gateway) the wire time is that of 4800 Bd.
  // false: every ordinary request waits `timeout` (a bare Client's default;
  // the tools' sessions, link::open_session, switch it on).
  bool adaptive_deadline = false;
  double turnaround_max_ms = 1.5;  // §6.1.1.1: the drive answers within 0.5-1.5 ms
  double deadline_margin_ms = 2.0;
  // Long operations: their answer deadlines. The manual gives §10.4 "could be
  // more than 1 s" (no upper bound), §11/§12 "timeout 10s", §13.1 "ca. 3 s";
  // real drives took longer (field reports, C1250 notes): "A command table flash save
  // took about 39 s and was never acknowledged", and "ROM writes and flash
  // saves left drives unresponsive for 30-90 s". 120 s covers the longest
  // silence measured (90 s) with a third to spare, for every long operation
  // (a reset or MC start after ROM writes meets the same silence). No
  // deadline may turn a slow, healthy drive into a failure (docs/field.md).
  Millis defaulting_timeout{120000};
  Millis flash_timeout{120000};
  Millis reset_timeout{120000};  // reset and MC start
  // A reset whose answer is expected to be lost (it comes at the new link
  // settings the reset takes, §13.1): waited this long (§13.1 "ca. 3 s", x2;
  // at most reset_timeout), then the drive is looked for at its new settings
  // for up to recover_timeout (link::reconnect_within).
  Millis relink_reset_timeout{6000};
  // After a long operation whose answer never came: how long find_again()
  // polls for the drive to answer again. 180 s: with the 120 s deadline the
  // 5 minutes the C1250 notes' client polls. 0: no
  // polling (the long operation's timeout is final).
  Millis recover_timeout{180000};
  int read_retries = 2;
  // Quiet time required after a lost/garbled answer before the next request.
  // With `adaptive_settle` on a link with a byte time (serial, simulated), the
  // quiet time is the deadline the failed exchange waited and, when no answer
  // came at all, at least twice the longest round trip timed so far; at most
  // `settle`: an answer later than that deadline + quiet time could meet a
  // later request whose answer carries no key (list get-next, block chunks).
  // On a TCP gateway (jitter unbounded) and without `adaptive_settle`: always
  // `settle`. With adaptive_deadline, a read whose answer arrived complete but
  // failed its checksum is retried at once, without waiting out its deadline,
  // after a shorter settle (corrupt_answer_quiet_us: the answer has come).
  Millis settle{500};
  bool adaptive_settle = false;
  // A modified list that ends at once with C6 for a UPID outside the layer is
  // an empty list, or a drive that reset between "start" and "get next" (it
  // forgot the list). true: read such a list three times (4 more telegrams per
  // empty layer) and accept it only if all agree. Lists with entries are
  // confirmed by a second pass when their C6 carries a UPID outside the layer.
  bool confirm_empty_lists = true;
  bool pad_ct_list = true;  // §12 example pads the defined-list request (the table: an erratum)
  bool skip_echo = true;    // 2-wire RS485 adapters may echo our own request
  // A default response whose length does not fit `layout` (the content is
  // configurable on the drive, §6.1.1.1, §15): true = take the layout of that
  // length closest to `layout` (codec::layout_for_length) from then on;
  // false = refuse it (the layout was given explicitly).
  bool adapt_layout = true;
  // ---- docs/reliability.md: fault-tolerant transfers and confirmed values ----
  // Every value that goes into a file is read this many times in agreement
  // (a further read breaks a tie). 0 = automatic: 2 when the checksum is off
  // and `link_has_parity` is false (nothing on the link detects a flipped bit),
  // else 1. The tools' sessions (link::open_session) use 0; a bare Client
  // reads once unless told.
  int agreeing_reads = 1;
  // Automatic mode only: once the link has shown that it corrupts answers (a
  // garbled frame, reads of one value that disagreed), this many reads must
  // agree from then on. Two answers can carry the same flipped value bit (on a
  // line flipping 3 % of answers about once per 150,000 reads: a wrong file
  // in about one of 200 backups); a third agreeing read makes that a triple
  // coincidence. 2 keeps the old behaviour.
  int noisy_agreeing_reads = 3;
  bool link_has_parity = false;  // set by whoever opens the link (parity even/odd)
  // A block or list transfer restarts from its setup/start telegram as long as
  // the restarts make progress: it gives up after `read_retries` + 1 passes in
  // a row that got no further, or after `transfer_deadline` in all.
  Millis transfer_deadline{120000};
  // Long operations (defaulting a layer, flash save, reset, MC start) have no
  // upper bound in the manual ("could be more than 1 s", §10.4): while one
  // runs, this is called about once a second with what is waited for and how
  // long it has taken so far.
  std::function<void(const std::string& what, Millis waited)> on_long_wait;
  // Set (e.g. by a SIGINT handler) to stop before the next telegram: a request
  // is never sent once it is true (Errc::interrupted); one in flight completes.
  const std::atomic<bool>* cancel = nullptr;
};

struct Stats {
  std::uint64_t requests = 0;
  std::uint64_t answers = 0;
  std::uint64_t bytes_tx = 0;
  std::uint64_t bytes_rx = 0;
  std::uint64_t retries = 0;
  std::uint64_t timeouts = 0;
  std::uint64_t bad_frames = 0;
  std::uint64_t write_requests = 0;    // telegrams that change drive state
  std::uint64_t stale_answers = 0;     // answers ignored: other sub ID or key than the request's
  std::uint64_t settles = 0;           // waits for a quiet line after a lost/garbled answer
  std::uint64_t settle_bytes = 0;      // bytes dropped while settling (late answers, noise)
  std::uint64_t writes_confirmed = 0;  // write answers lost, effect confirmed by reading back
  std::uint64_t extra_reads = 0;       // reads made to confirm a value (agreeing_reads > 1)
  std::uint64_t disagreements = 0;     // values whose reads disagreed (a tie broken by more reads)
  std::uint64_t third_reads = 0;       // reads of one value beyond the second (noisy line, ties)
  std::uint64_t block_passes = 0;      // passes of block reads (1 per block on a clean line)
  std::uint64_t block_rewrites = 0;    // block writes restarted from their setup telegram
  std::uint64_t undocumented_states = 0;  // answers with a state the manual does not list
  std::uint64_t rtt_samples = 0;          // answers timed for the adaptive deadline
  std::uint64_t late_answers = 0;      // settles that dropped bytes (an answer after its deadline)
  std::uint64_t max_deadline_us = 0;   // longest ordinary deadline used
  std::uint64_t last_deadline_us = 0;  // the deadline of the last ordinary request
};

// How this drive answers a probe of an ID that holds nothing (the manual does
// not say, §11/§12): recorded by the first probe that finds nothing.
struct ProbeForms {
  // Curve "read sizes" (04h 08h) of an empty ID: nullopt = not seen yet,
  // 00h = sizes 0/0, else the error state answered (e.g. C8h).
  std::optional<std::uint8_t> empty_curve;
  // CT "setup read" (08h 05h) of an undefined entry: 00h = size 0, else the state.
  std::optional<std::uint8_t> empty_ct_entry;
};

struct ModifiedParam {
  std::uint16_t upid = 0;
  std::uint32_t value = 0;
  friend bool operator==(const ModifiedParam&, const ModifiedParam&) = default;
};

struct UpidInfo {
  std::uint16_t upid = 0;
  std::uint16_t address_usage = 0;
  std::uint16_t type = 0;
  friend bool operator==(const UpidInfo&, const UpidInfo&) = default;
};

struct CurveSizes {
  std::uint16_t info = 0;
  std::uint16_t data = 0;
};

// What a protocol can do that the operations ask before planning (LinUDP
// lacks some LinRS requests, LinUDP V2 p13-p19).
struct Capabilities {
  bool delete_one_curve = true;    // LinRS 04h 02h; LinUDP has none (LinUDP V2 p13-p15)
  bool parameter_type = true;      // LinRS 05h 04h; LinUDP has none (LinUDP V2 p14)
  std::string protocol = "LinRS";  // "LinRS", "LinUDP"
};

// The drive as the operations see it: one interface both protocols implement
// (LinrsClient below over a byte link, linudp::Client over UDP datagrams),
// so backup, diff, restore, default, undo, get/set and info have one path.
// The contract of each call is LinRS's (below, with the seed 003 sections);
// a protocol without a request answers with a refusal (ErrorClass::drive_refusal)
// that names what it lacks.
class Client {
 public:
  virtual ~Client() = default;
  Client(const Client&) = delete;
  Client& operator=(const Client&) = delete;

  const ClientOptions& options() const { return opt_; }
  virtual void set_options(const ClientOptions& o) { opt_ = o; }
  const Stats& stats() const { return stats_; }
  const ProbeForms& probe_forms() const { return forms_; }
  virtual Capabilities capabilities() const = 0;
  // Reads per value actually used (see LinrsClient).
  virtual int agreeing_reads() const { return 1; }
  virtual bool noise_seen() const { return false; }
  virtual transport::Transport& link() = 0;

  virtual Result<codec::DefaultResponse> default_response(
      codec::ResponseRequest kind = codec::ResponseRequest::default_response) = 0;
  virtual Result<std::uint32_t> read_ram(std::uint16_t upid) = 0;
  virtual Result<void> write_ram(std::uint16_t upid, std::uint32_t value) = 0;
  virtual Result<void> write_ram_rom(std::uint16_t upid, std::uint32_t value) = 0;
  virtual Result<std::uint32_t> read_rom(std::uint16_t upid) = 0;
  virtual Result<void> write_rom(std::uint16_t upid, std::uint32_t value) = 0;
  virtual Result<void> write_rom_confirmed(std::uint16_t upid, std::uint32_t value) = 0;
  virtual Result<std::uint16_t> get_type(std::uint16_t upid) = 0;
  virtual Result<std::uint32_t> get_min(std::uint16_t upid) = 0;
  virtual Result<std::uint32_t> get_max(std::uint16_t upid) = 0;
  virtual Result<std::uint32_t> get_default(std::uint16_t upid) = 0;
  virtual Result<std::optional<std::uint16_t>> read_address_usage(std::uint16_t upid) = 0;
  virtual Result<std::vector<ModifiedParam>> modified_list(int layer) = 0;
  virtual Result<std::vector<UpidInfo>> upid_list(
      int layer, const std::function<void(std::size_t)>& progress = {}) = 0;
  virtual Result<void> default_layer(int layer) = 0;
  virtual Result<Millis> find_again(const std::string& what) = 0;
  virtual Result<std::optional<CurveSizes>> curve_sizes(std::uint16_t curve) = 0;
  virtual Result<Bytes> read_curve_info(std::uint16_t curve, std::uint16_t size) = 0;
  virtual Result<Bytes> read_curve_data(std::uint16_t curve, std::uint16_t size) = 0;
  struct CurveBlocks {
    Bytes info;
    Bytes data;
  };
  virtual Result<std::optional<CurveBlocks>> read_curve(std::uint16_t curve) = 0;
  virtual Result<void> write_curve(std::uint16_t curve, ByteView info, ByteView data) = 0;
  virtual Result<void> delete_curve(std::uint16_t curve) = 0;
  virtual Result<void> delete_all_curves() = 0;
  virtual Result<void> save_curves() = 0;
  virtual Result<std::vector<std::uint16_t>> ct_defined_entries() = 0;
  virtual Result<Bytes> read_ct_entry(std::uint16_t entry) = 0;
  virtual Result<void> write_ct_entry(std::uint16_t entry, ByteView bytes) = 0;
  virtual Result<void> delete_ct_entry(std::uint16_t entry) = 0;
  virtual Result<void> delete_all_ct() = 0;
  virtual Result<void> save_ct() = 0;
  virtual Result<std::optional<Bytes>> probe_ct_entry(std::uint16_t entry) = 0;
  virtual Result<void> stop_mc() = 0;
  virtual Result<void> start_mc() = 0;
  virtual Result<void> reset() = 0;
  virtual Result<void> reset(Millis timeout) = 0;
  virtual Result<std::string> actual_error_text() = 0;
  virtual Result<std::string> error_text(std::uint16_t code) = 0;
  virtual Result<codec::ErrorCounters> error_counters() = 0;
  virtual Result<codec::ErrorLogEntry> error_log_entry(std::uint16_t index) = 0;

 protected:
  explicit Client(ClientOptions opt) : opt_(std::move(opt)) {}
  ClientOptions opt_;
  Stats stats_;
  ProbeForms forms_;
};

// LinRS over a byte link (serial, TCP gateway, simulated line).
class LinrsClient final : public Client {
 public:
  LinrsClient(transport::Transport& link, ClientOptions opt);

  Capabilities capabilities() const override { return {}; }
  // Reads per value actually used (agreeing_reads resolved; in automatic mode
  // it rises to noisy_agreeing_reads once the line has shown corruption).
  int agreeing_reads() const override;
  // The line has shown corruption (garbled frames, disagreeing reads).
  bool noise_seen() const override { return noise_seen_; }
  transport::Transport& link() override { return link_; }

  // Sends `req` and waits for the answer the request's group defines.
  // idempotent: may be retried on timeout/garbled answer. A read (not
  // is_write_request) with `timeout` equal to options().timeout, outside a long
  // operation, is an ordinary read: with adaptive_deadline it waits
  // answer_deadline_us(req) instead.
  Result<codec::Telegram> transact(const codec::Telegram& req, Millis timeout, bool idempotent);
  // The deadline the next ordinary request `req` would wait (adaptive_deadline;
  // else options().timeout), in microseconds, and its floor (no measurement).
  std::int64_t answer_deadline_us(const codec::Telegram& req) const;
  std::int64_t deadline_floor_us(const codec::Telegram& req) const;
  // Quiet time after an ordinary read's answer that arrived complete but
  // failed its checksum (adaptive timing): the link's receive latency + the
  // deadline margin + 2 byte times.
  std::int64_t corrupt_answer_quiet_us() const;
  // Smoothed excess round trip (answer time minus wire time) and its variation,
  // microseconds; srtt < 0 until the first answer has been timed.
  double srtt_us() const { return srtt_us_; }
  double rttvar_us() const { return rttvar_us_; }

  // §6
  Result<codec::DefaultResponse> default_response(
      codec::ResponseRequest kind = codec::ResponseRequest::default_response) override;
  // §7, §8
  Result<codec::DefaultResponse> write_control_word(std::uint16_t cw);

  // §9 (live values, RAM)
  Result<std::uint32_t> read_ram(std::uint16_t upid) override;
  Result<void> write_ram(std::uint16_t upid, std::uint32_t value) override;
  Result<void> write_ram_rom(std::uint16_t upid, std::uint32_t value) override;

  // §10 parameter configuration
  Result<std::uint32_t> read_rom(std::uint16_t upid) override;
  Result<void> write_rom(std::uint16_t upid, std::uint32_t value) override;
  // write_rom, and when its answer is lost or garbled, read the ROM value back
  // (never resend): success only if the drive holds `value`.
  Result<void> write_rom_confirmed(std::uint16_t upid, std::uint32_t value) override;
  Result<std::uint16_t> get_type(std::uint16_t upid) override;
  Result<std::uint32_t> get_min(std::uint16_t upid) override;
  Result<std::uint32_t> get_max(std::uint16_t upid) override;
  Result<std::uint32_t> get_default(std::uint16_t upid) override;
  // LinRS 3V27 p27 (05h sub 03h, answer 53h): the address usage of one UPID,
  // the low word of the answer's value. A drive of the seed's generation does
  // not know the request: its C3h/C4h answer is nullopt (use the UPID list,
  // §10.3). Other refusals (C8h unknown UPID) are errors.
  Result<std::optional<std::uint16_t>> read_address_usage(std::uint16_t upid) override;
  // Modified-UPID list of a layer (§10.2). C6 ends the list; its UPID counts
  // once, only if it lies in the layer's range and was not already received
  // (LinRS §10.2-§10.3, erratum: §10.2's C6 answer carries a UPID not listed
  // before, §10.3's repeats the previous one).
  Result<std::vector<ModifiedParam>> modified_list(int layer) override;
  // UPID list of a layer with address usage and type (§10.3), same C6 rule.
  Result<std::vector<UpidInfo>> upid_list(
      int layer, const std::function<void(std::size_t)>& progress = {}) override;
  // ROM of a layer to defaults (§10.4); answer after completion (> 1 s).
  Result<void> default_layer(int layer) override;

  // After a long operation (default_layer, save_curves, save_ct, start_mc,
  // reset) failed with Errc::timeout: its answer never came, which a slow
  // drive does (field reports, C1250 notes), so the drive is looked for again.
  // Polls with the cheapest read (§6 default response request, one attempt
  // each, input settled between) until the drive answers (any valid answer,
  // a refusal included) or `recover_timeout` of link time has passed, calling
  // on_long_wait about once a second with "waiting for drive 11h to answer
  // again after WHAT". Returns the link time it took; Errc::timeout naming
  // WHAT, the polls and the budget when the drive stayed silent; a link that
  // closed or an interruption as they come. It never resends the operation:
  // what the drive holds is for the caller to read back.
  Result<Millis> find_again(const std::string& what) override;

  // §11 curves. curve_sizes: nullopt when the drive reports no such curve (sizes 0).
  Result<std::optional<CurveSizes>> curve_sizes(std::uint16_t curve) override;
  Result<Bytes> read_curve_info(std::uint16_t curve, std::uint16_t size) override;
  Result<Bytes> read_curve_data(std::uint16_t curve, std::uint16_t size) override;
  // Reads sizes, info and data; restarts the block transfer on a lost chunk.
  Result<std::optional<CurveBlocks>> read_curve(std::uint16_t curve) override;
  Result<void> write_curve(std::uint16_t curve, ByteView info, ByteView data) override;
  Result<void> delete_curve(std::uint16_t curve) override;
  Result<void> delete_all_curves() override;
  Result<void> save_curves() override;

  // §12 command table
  Result<std::vector<std::uint16_t>> ct_defined_entries() override;
  Result<Bytes> read_ct_entry(std::uint16_t entry) override;
  Result<void> write_ct_entry(std::uint16_t entry, ByteView bytes) override;
  Result<void> delete_ct_entry(std::uint16_t entry) override;
  Result<void> delete_all_ct() override;
  Result<void> save_ct() override;
  // Entry bytes, or nullopt when the drive says the entry holds nothing (size
  // 0 or an error state in answer to the setup read): the form is recorded.
  Result<std::optional<Bytes>> probe_ct_entry(std::uint16_t entry) override;

  // §13
  Result<void> stop_mc() override;
  Result<void> start_mc() override;  // answer after completion
  Result<void> reset() override;     // answer after completion (~3 s)
  // The same, waiting `timeout` for the answer (relink_reset_timeout).
  Result<void> reset(Millis timeout) override;

  // §14
  Result<std::string> actual_error_text() override;
  Result<std::string> error_text(std::uint16_t code) override;
  Result<codec::ErrorCounters> error_counters() override;
  Result<codec::ErrorLogEntry> error_log_entry(std::uint16_t index) override;

 private:
  Result<codec::IdValueResponse> cfg(codec::CfgOp op, std::uint16_t upid, bool idempotent,
                                     Millis timeout);
  Result<codec::IdValueResponse> id_value(const codec::Telegram& req, std::uint8_t expected_sub,
                                          bool idempotent, Millis timeout);
  Result<Bytes> read_block(const codec::Telegram& setup, std::uint8_t setup_sub,
                           const codec::Telegram& chunk_req, std::uint8_t chunk_sub,
                           std::size_t size, const char* what);

  // decode_default_response with opt_.layout, adapting it (adapt_layout) to the
  // answer's length; value_expected: a read or response request 02-04.
  Result<codec::DefaultResponse> decode_default(const codec::Telegram& t, bool value_expected);

  // Reads and drops input until the line has been quiet for opt_.settle.
  Result<void> settle_line();
  // The phases of transact(): send one attempt (settle, deadline, write;
  // returns the deadline in microseconds), await the answer (nullopt at the
  // deadline), pick this request's answer out of the decoded frames, the
  // drive's refusal in an answer, and the error of an attempt without a
  // valid answer.
  struct Exchange;
  Result<std::int64_t> send_attempt(Exchange& x);
  Result<std::optional<codec::Telegram>> await_answer(Exchange& x, std::int64_t deadline_us);
  std::optional<codec::Telegram> match_answer(Exchange& x);
  std::optional<Error> refusal_in(const Exchange& x, const codec::Telegram& answer);
  Error attempt_failed(Exchange& x, std::int64_t deadline_us);
  // Reads until agreeing_reads() answers agree (refusals count as answers).
  template <class T, class F>
  Result<T> agreed(F&& read);
  // The same with the number of agreeing reads an answer needs given by
  // `need_for(answer)` (an answer a single flipped bit cannot produce from
  // another plausible one needs fewer).
  template <class T, class F, class N>
  Result<T> agreed(F&& read, N&& need_for);
  Result<std::vector<ModifiedParam>> modified_list_once(int layer);
  // The steps of modified_list (lists.cpp): one pass of "get next" after a
  // "start" (the outer error ends the list, the inner one only the pass, with
  // `reached` the position it got to), and the vote over complete passes (a
  // result once decided, nullopt while another pass is needed).
  struct ModifiedPass;
  Result<std::optional<Error>> modified_pass(int layer, ModifiedPass& pass, std::size_t& reached);
  std::optional<Result<std::vector<ModifiedParam>>> vote_modified(
      std::vector<std::vector<ModifiedParam>>& complete, ModifiedPass& pass,
      const std::string& lname);
  Result<std::vector<UpidInfo>> upid_list_once(int layer,
                                               const std::function<void(std::size_t)>& progress);
  // One pass of a block read; fills votes; see blocks.cpp.
  struct BlockVotes;
  Result<void> block_pass(const codec::Telegram& chunk_req, std::uint8_t chunk_sub,
                          std::size_t chunks, BlockVotes& votes, const char* what);
  // Waits for a long operation's answer in slices, reporting progress.
  Result<codec::Telegram> transact_long(const codec::Telegram& req, Millis timeout,
                                        const std::string& what);

  transport::Transport& link_;
  codec::StreamDecoder decoder_;
  bool unsettled_ = false;  // the last exchange ended without its answer
  // Adaptive deadline state (microseconds): see ClientOptions::adaptive_deadline.
  void rtt_sample(double excess_us);
  double wire_us(std::size_t bytes) const;
  double srtt_us_ = -1.0, rttvar_us_ = 0.0;
  double max_rtt_us_ = 0.0;           // longest round trip timed, wire time included
  int backoff_ = 0;                   // doublings after timeouts, until the next timed answer
  std::int64_t last_send_ns_ = 0;     // link time before the last request was written
  std::int64_t settle_quiet_us_ = 0;  // quiet time of the next settle (adaptive_settle)
  bool noise_seen_ = false;           // corruption seen on this link (agreeing_reads)
  std::string long_wait_;             // what a long operation in flight waits for (transact_long)
};

}  // namespace lmcfg::client
