// Curves (LinRS §11) and the command table (§12): block transfers.
//
// Block reads go in passes, each from the setup telegram ("read sizes" for a
// curve, "setup read" for a CT entry) to the last chunk. The manual gives no
// way to ask for a chunk by position, so a lost chunk answer is a hole: the
// pass goes on assuming the drive's cursor moved on (the answer, not the
// request, was lost) and the drive's state at the last chunk (00h exactly
// there) confirms it; if it does not, only the reads before the first hole
// that check out count (BlockVotes::checked_prefix). Each chunk position
// collects the values read for it; it is decided when agreeing_reads() reads
// agree (a further read breaks a tie). Passes go on while they decide more
// positions (RestartBudget), so a long curve survives a line that loses
// answers without restarting from zero each time. A pass after the first may
// stop at the last position still undecided when its reads check out the same
// way: its next telegram is a setup telegram.
//
// Block writes go in passes too: setup (add / setup write), then every chunk
// once. A lost chunk answer is not resent; when a pass lost any answer, the
// block is read back and compared, and a mismatch restarts the object's write
// from its setup telegram (a curve is deleted and added again).
#include <cstdio>
#include <set>

#include "client/client.hpp"
#include "client/internal.hpp"

namespace lmcfg::client {

using namespace codec;
using detail::hexid;
using detail::is_link_error;
using detail::RestartBudget;

struct LinrsClient::BlockVotes {
  struct Count {
    std::uint32_t value = 0;
    int n = 0;
  };
  std::vector<std::vector<Count>> at;  // per chunk position
  int passes = 0;
  bool stop_early_allowed = true;
  // The bytes of the last chunk that belong to the block. The rest is padding
  // (a 70-byte curve info block ends 2 bytes into its 18th chunk), and real
  // drives leave stale data there (EtherCAT curves: "the two bytes after the
  // 70-byte info block are not zero (stale data) and must not be taken as part
  // of the block or compared"): masked before a read is kept or compared.
  std::uint32_t last_mask = 0xFFFFFFFFu;
  explicit BlockVotes(std::size_t chunks) : at(chunks) {}
  void add(std::size_t i, std::uint32_t v) {
    for (auto& c : at[i]) {
      if (c.value == v) {
        ++c.n;
        return;
      }
    }
    at[i].push_back({v, 1});
  }
  // The decided value of position i: `need` reads agree and no other value has as many.
  std::optional<std::uint32_t> decided(std::size_t i, int need) const {
    const Count* best = nullptr;
    int second = 0;
    for (const auto& c : at[i]) {
      if (!best || c.n > best->n) {
        if (best) second = std::max(second, best->n);
        best = &c;
      } else {
        second = std::max(second, c.n);
      }
    }
    if (!best || best->n < need || best->n == second) return std::nullopt;
    return best->value;
  }
  // Votes that count towards deciding (at most `need` per position): grows
  // with every pass that brought a useful read.
  std::size_t mass(int need) const {
    std::size_t m = 0;
    for (const auto& a : at) {
      int best = 0;
      for (const auto& c : a) best = std::max(best, c.n);
      m += static_cast<std::size_t>(std::min(best, need + 1));
    }
    return m;
  }
  std::size_t decided_count(int need) const {
    std::size_t n = 0;
    for (std::size_t i = 0; i < at.size(); ++i) n += decided(i, need) ? 1 : 0;
    return n;
  }
  bool disagreed() const {
    for (const auto& a : at)
      if (a.size() > 1) return true;
    return false;
  }

  // Values decided before a pass (nullopt: undecided).
  std::vector<std::optional<std::uint32_t>> known(int need) const {
    std::vector<std::optional<std::uint32_t>> k(at.size());
    for (std::size_t i = 0; i < at.size(); ++i) k[i] = decided(i, need);
    return k;
  }

  // How many of the pass's first reads `got[0..upto)` may count when no end
  // state (00h exactly at the last chunk) confirms where the drive's cursor
  // was. Nothing positions a block read (§11, §12): a drive that restarted its
  // cursor (a reset) answers chunks from before the ones asked for, with state
  // 04h; only the end state shows it. Counted: the reads up to the first hole,
  // the first decided position that read another value than its decided one,
  // or the first undecided position that read a value an earlier position
  // holds (decided, or read in this pass). The first answer from behind the
  // cursor at an undecided position repeats an earlier value, so it and
  // everything after it are left out; answers from behind at decided
  // positions that still matched add nothing wrong.
  static std::size_t checked_prefix(const std::vector<std::optional<std::uint32_t>>& known,
                                    const std::vector<std::optional<std::uint32_t>>& got,
                                    std::size_t upto) {
    std::set<std::uint32_t> before;
    for (std::size_t i = 0; i < upto; ++i) {
      if (!got[i]) return i;
      if (known[i] ? *got[i] != *known[i] : before.count(*got[i]) > 0) return i;
      before.insert(*got[i]);
    }
    return upto;
  }
};

Result<void> LinrsClient::block_pass(const Telegram& chunk_req, std::uint8_t chunk_sub,
                                     std::size_t chunks, BlockVotes& votes, const char* what) {
  std::vector<std::optional<std::uint32_t>> got(chunks);
  std::size_t first_hole = chunks;
  std::optional<Error> problem;
  bool end_confirmed = false;
  const int need = agreeing_reads();
  const auto known = votes.known(need);
  // A pass after the first may stop at the last undecided position when its
  // reads check out (checked_prefix): the next telegram is a setup telegram.
  // Not where one read is not trusted (need > 1): there every further read of
  // a decided position is one more chance to see two identical bit flips
  // disagree, and stopping early saved no time (docs/reliability.md).
  std::optional<std::size_t> stop_at;
  if (votes.passes++ > 0 && votes.stop_early_allowed && need == 1) {
    for (std::size_t i = chunks; i-- > 0;) {
      if (known[i]) continue;
      if (i + 1 < chunks) stop_at = i;
      break;
    }
  }
  bool stopped = false;
  for (std::size_t i = 0; i < chunks; ++i) {
    auto r = id_value(chunk_req, chunk_sub, false, opt_.timeout);
    const bool last_chunk = i + 1 == chunks;
    if (!r.ok()) {
      if (!is_link_error(r.error())) return std::move(r).error();
      if (first_hole == chunks) first_hole = i;
      problem =
          Error(r.error().code, std::string(what) + ": chunk " + std::to_string(i + 1) + " of " +
                                    std::to_string(chunks) + ": " + r.error().message);
      continue;  // the drive's cursor has probably moved on: a hole, checked at the end
    }
    const std::uint8_t want = last_chunk ? state::ok : state::more_data;
    if (r->state != want) {
      // The drive's cursor is not where ours is (a lost request, a reset, a
      // flipped state bit): only reads before the first hole count (checked).
      problem = Error(Errc::unexpected_response,
                      std::string(what) + ": chunk " + std::to_string(i + 1) + " of " +
                          std::to_string(chunks) + " has state " + hexid("%02Xh", r->state) +
                          ", expected " + hexid("%02Xh", want));
      first_hole = std::min(first_hole, i);
      break;
    }
    got[i] = last_chunk ? r->value & votes.last_mask : r->value;
    if (last_chunk) end_confirmed = true;
    if (stop_at && i == *stop_at && BlockVotes::checked_prefix(known, got, i + 1) == i + 1) {
      stopped = true;
      break;
    }
  }
  // Where one read decides (need 1), a read that no end state confirms must
  // check out; where reads must agree, one shifted read cannot decide alone.
  std::size_t certain = first_hole;
  if (end_confirmed || stopped)
    certain = chunks;
  else if (need == 1)
    certain = BlockVotes::checked_prefix(known, got, first_hole);
  for (std::size_t i = 0; i < certain; ++i)
    if (got[i]) votes.add(i, *got[i]);
  if (problem) return std::move(*problem);
  return {};
}

Result<Bytes> LinrsClient::read_block(const Telegram& setup, std::uint8_t setup_sub,
                                      const Telegram& chunk_req, std::uint8_t chunk_sub,
                                      std::size_t size, const char* what) {
  const std::size_t chunks = (size + 3) / 4;
  BlockVotes votes(chunks);
  if (size % 4 != 0) votes.last_mask = (1u << (8 * (size % 4))) - 1;
  // A curve's data block is read right after its info block without a setup
  // telegram (§11.1): the info block's passes read to its end, so that a
  // drive with one block cursor is where the data block starts.
  votes.stop_early_allowed = !(chunk_req.main == static_cast<std::uint8_t>(Main::curve) &&
                               chunk_req.sub == static_cast<std::uint8_t>(CurveOp::read_info));
  RestartBudget budget(opt_.read_retries + 1, opt_.transfer_deadline);
  Error last(Errc::timeout, "");
  for (bool first = true;; first = false) {
    if (!first) {
      // Restart the transfer from its setup telegram (resets the drive's block cursor).
      auto s = id_value(setup, setup_sub, true, opt_.timeout);
      if (!s.ok()) return std::move(s).error();
    }
    ++stats_.block_passes;
    auto pass = block_pass(chunk_req, chunk_sub, chunks, votes, what);
    if (!pass.ok() && !is_link_error(pass.error())) return std::move(pass).error();
    if (votes.disagreed()) noise_seen_ = true;  // one position read two ways: bits flip
    const int need = agreeing_reads();
    const std::size_t done = votes.decided_count(need);
    if (done == chunks) {
      if (votes.disagreed()) ++stats_.disagreements;
      Bytes out;
      out.reserve(chunks * 4);
      for (std::size_t i = 0; i < chunks; ++i) {
        const std::uint32_t v = *votes.decided(i, need);
        for (int k = 0; k < 4; ++k) out.push_back(static_cast<std::uint8_t>(v >> (8 * k)));
      }
      out.resize(size);  // the last chunk carries padding
      return out;
    }
    if (pass.ok()) {
      ++stats_.extra_reads;
      last = Error(Errc::unexpected_response, std::to_string(chunks - done) + " of " +
                                                  std::to_string(chunks) + " chunks without " +
                                                  std::to_string(need) + " agreeing reads");
    } else {
      last = std::move(pass).error();
    }
    if (!budget.another(votes.mass(need))) break;
    ++stats_.retries;
  }
  last.message = last.message + " (after " + std::to_string(budget.passes()) + " passes)";
  return last;
}

// ---- curves (§11) ----

namespace {
// A refusal in answer to a probe means "nothing there", except the states
// that say the request itself did not arrive intact (C1, C2) or at the wrong
// baud rate (C5), and C3h: LinRS §16.1 "C3h Undefined Message Main ID" says
// the drive does not know the message group at all (a B1100 has no curve or
// command table group, LinRS 3V27 §11-§12), not that this ID is empty. It is
// returned as the error, and backup and the restore plan take it as "no such
// group" (ops/backup.hpp no_such_group).
bool probe_refusal(const Error& e) {
  if (e.code.category() != comm_state_category()) return false;
  const int s = e.code.value();
  return s != 0xC1 && s != 0xC2 && s != 0xC3 && s != 0xC5;
}
}  // namespace

Result<std::optional<CurveSizes>> LinrsClient::curve_sizes(std::uint16_t curve) {
  auto sizes = agreed<std::uint32_t>(
      [&]() -> Result<std::uint32_t> {
        LMCFG_ASSIGN_OR_RETURN(auto r, id_value(make_curve(opt_.id, CurveOp::read_sizes, curve),
                                                0x40, true, opt_.timeout));
        if (r.key != curve) {
          return Error(Errc::unexpected_response, "curve size query for ID " +
                                                      std::to_string(curve) + " answered for ID " +
                                                      std::to_string(r.key));
        }
        return r.value;
      },
      [&](const Result<std::uint32_t>& r) {
        // "Nothing here" (zero sizes, or a refusal: a state of C1h or above, at
        // least three bits from 00h) is two or more flipped bits away from a
        // curve's answer (state 00h, info and data block sizes both non-zero,
        // §11): the same single flip in two answers, which a third read guards
        // against on a corrupting line, cannot make a curve look absent. Two
        // agreeing reads stay required.
        const bool nothing_here = r.ok() ? *r == 0 : probe_refusal(r.error());
        return nothing_here ? std::min(agreeing_reads(), 2) : agreeing_reads();
      });
  if (!sizes.ok()) {
    if (!probe_refusal(sizes.error())) return std::move(sizes).error();
    // An error state for a probe: no curve under this ID (§11 leaves the answer open).
    if (!forms_.empty_curve)
      forms_.empty_curve = static_cast<std::uint8_t>(sizes.error().code.value());
    return std::optional<CurveSizes>();
  }
  CurveSizes s{static_cast<std::uint16_t>(*sizes & 0xFFFF),
               static_cast<std::uint16_t>(*sizes >> 16)};
  if (s.info == 0 && s.data == 0) {
    if (!forms_.empty_curve) forms_.empty_curve = state::ok;
    return std::optional<CurveSizes>();
  }
  return std::optional<CurveSizes>(s);
}

Result<Bytes> LinrsClient::read_curve_info(std::uint16_t curve, std::uint16_t size) {
  return read_block(make_curve(opt_.id, CurveOp::read_sizes, curve), 0x40,
                    make_curve(opt_.id, CurveOp::read_info, curve), 0x40, size,
                    ("curve " + std::to_string(curve) + " info block").c_str());
}
Result<Bytes> LinrsClient::read_curve_data(std::uint16_t curve, std::uint16_t size) {
  return read_block(make_curve(opt_.id, CurveOp::read_sizes, curve), 0x40,
                    make_curve(opt_.id, CurveOp::read_data, curve), 0x40, size,
                    ("curve " + std::to_string(curve) + " data block").c_str());
}

Result<std::optional<LinrsClient::CurveBlocks>> LinrsClient::read_curve(std::uint16_t curve) {
  LMCFG_ASSIGN_OR_RETURN(auto sizes, curve_sizes(curve));
  if (!sizes) return std::optional<CurveBlocks>();
  CurveBlocks b;
  LMCFG_ASSIGN_OR_RETURN(b.info, read_curve_info(curve, sizes->info));
  LMCFG_ASSIGN_OR_RETURN(b.data, read_curve_data(curve, sizes->data));
  return std::optional<CurveBlocks>(std::move(b));
}

namespace {
std::array<std::uint8_t, 4> chunk_at(ByteView b, std::size_t i) {
  std::array<std::uint8_t, 4> c{0, 0, 0, 0};
  for (std::size_t k = 0; k < 4 && i * 4 + k < b.size(); ++k) c[k] = b[i * 4 + k];
  return c;
}

// Outcome of one write pass.
struct WritePass {
  bool lost_answers = false;    // some answer lost: the result must be read back
  std::optional<Error> failed;  // the drive showed the transfer broke (state, refusal)
};

// Sends the chunks of one block once. A block write answers 04h while the
// drive expects more and 00h after the last chunk; anything else means the
// drive lost the transfer (a reset, a lost request): the pass failed.
template <class Send>
void write_chunks(ByteView block, const std::string& what, WritePass& pass, Send&& send) {
  const std::size_t chunks = (block.size() + 3) / 4;
  for (std::size_t i = 0; i < chunks && !pass.failed; ++i) {
    Result<IdValueResponse> r = send(chunk_at(block, i));
    const bool last_chunk = i + 1 == chunks;
    std::string where = what + ", chunk " + std::to_string(i + 1) + " of " + std::to_string(chunks);
    if (!r.ok()) {
      if (is_link_error(r.error())) {
        pass.lost_answers = true;  // not resent: the read-back decides
        continue;
      }
      pass.failed = Error(r.error().code, where + ": " + r.error().message);
      return;
    }
    const std::uint8_t want = last_chunk ? state::ok : state::more_data;
    if (r->state != want) {
      pass.failed =
          Error(Errc::unexpected_response,
                where + ": the drive answered state " + hexid("%02Xh", r->state) + ", expected " +
                    hexid("%02Xh", want) + " (block transfer lost on the drive?)");
    }
  }
}

// After one write pass: nullopt = write again from the setup telegram, else the
// outcome. A pass with lost answers is settled by reading the object back
// (`read_back`: whether the drive holds exactly what was written, nullopt when
// it holds nothing there); a write is never repeated without that evidence.
template <class ReadBack>
std::optional<Result<void>> settle_write_pass(WritePass& pass, RestartBudget& budget,
                                              const std::string& name, ReadBack&& read_back,
                                              std::uint64_t& confirmed) {
  // A refusal after a lost "add"/setup answer: the setup did not land; write again.
  if (pass.failed && !pass.lost_answers && !is_link_error(*pass.failed))
    return Result<void>(std::move(*pass.failed));
  if (!pass.failed && !pass.lost_answers) return Result<void>{};
  std::size_t progress = 0;
  if (!pass.failed) {
    Result<std::optional<bool>> back = read_back();
    if (!back.ok()) return Result<void>(std::move(back).error());
    if (*back == true) {
      ++confirmed;
      return Result<void>{};
    }
    pass.failed =
        Error(Errc::unexpected_response, name + ": read back differs from what was written");
    if (back->has_value()) progress = 1;
  }
  if (!budget.another(progress)) {
    Error e = std::move(*pass.failed);
    e.message += " (after " + std::to_string(budget.passes()) + " write passes)";
    return Result<void>(std::move(e));
  }
  return std::nullopt;
}
}  // namespace

Result<void> LinrsClient::write_curve(std::uint16_t curve, ByteView info, ByteView data) {
  if (info.size() > 0xFFFF || data.size() > 0xFFFF) {
    return Error(Errc::invalid_argument,
                 "curve " + std::to_string(curve) + " blocks exceed 65535 bytes");
  }
  const std::string name = "curve " + std::to_string(curve);
  RestartBudget budget(opt_.read_retries + 1, opt_.transfer_deadline);
  for (int pass_no = 0;; ++pass_no) {
    WritePass pass;
    if (pass_no > 0) {
      // Start the curve's write again from its setup telegram: delete, add.
      ++stats_.block_rewrites;
      auto del = delete_curve(curve);
      if (!del.ok() && !is_link_error(del.error())) return std::move(del).error();
    }
    auto add = id_value(make_curve_add(opt_.id, curve, static_cast<std::uint16_t>(info.size()),
                                       static_cast<std::uint16_t>(data.size())),
                        0x40, false, opt_.timeout);
    if (!add.ok()) {
      if (!is_link_error(add.error())) return std::move(add).error();
      pass.lost_answers = true;
    }
    for (auto [op, block] :
         {std::pair{CurveOp::write_info, info}, std::pair{CurveOp::write_data, data}}) {
      const std::string what = name + (op == CurveOp::write_info ? " info" : " data") + " block";
      write_chunks(block, what, pass, [&, op = op](std::array<std::uint8_t, 4> c) {
        return id_value(make_curve_write(opt_.id, op, curve, c), 0x40, false, opt_.timeout);
      });
    }
    auto done = settle_write_pass(
        pass, budget, name,
        [&]() -> Result<std::optional<bool>> {
          LMCFG_ASSIGN_OR_RETURN(auto back, read_curve(curve));
          if (!back) return std::optional<bool>{};
          return std::optional<bool>{back->info == Bytes(info.begin(), info.end()) &&
                                     back->data == Bytes(data.begin(), data.end())};
        },
        stats_.writes_confirmed);
    if (done) return std::move(*done);
  }
}

Result<void> LinrsClient::delete_curve(std::uint16_t curve) {
  LMCFG_TRY(id_value(make_curve(opt_.id, CurveOp::delete_one, curve), 0x40, false, opt_.timeout));
  return {};
}
Result<void> LinrsClient::delete_all_curves() {
  LMCFG_TRY(id_value(make_curve(opt_.id, CurveOp::delete_all), 0x40, false, opt_.timeout));
  return {};
}
Result<void> LinrsClient::save_curves() {
  LMCFG_ASSIGN_OR_RETURN(auto t, transact_long(make_curve(opt_.id, CurveOp::save_to_flash),
                                               opt_.flash_timeout, "saving curves to flash"));
  LMCFG_TRY(decode_id_value(t, 0x40));
  return {};
}

// ---- command table (§12) ----

Result<std::vector<std::uint16_t>> LinrsClient::ct_defined_entries() {
  std::vector<std::uint16_t> out;
  for (std::uint16_t block = 0; block < 8; ++block) {
    LMCFG_ASSIGN_OR_RETURN(auto bits, agreed<std::uint32_t>([&]() -> Result<std::uint32_t> {
                             LMCFG_ASSIGN_OR_RETURN(
                                 auto r,
                                 id_value(make_ct_defined_list(opt_.id, block, opt_.pad_ct_list),
                                          0x87, true, opt_.timeout));
                             if (r.key != block) {
                               return Error(Errc::unexpected_response,
                                            "CT defined-entry list block " + std::to_string(block) +
                                                " answered for block " + std::to_string(r.key));
                             }
                             return r.value;
                           }));
    for (unsigned bit = 0; bit < 32; ++bit) {
      if ((bits & (1u << bit)) == 0)
        out.push_back(static_cast<std::uint16_t>(block * 32 + bit));  // 0 = exists
    }
  }
  return out;
}

Result<std::optional<Bytes>> LinrsClient::probe_ct_entry(std::uint16_t entry) {
  auto setup = make_ct(opt_.id, CtOp::setup_read, entry);
  auto size = agreed<std::uint32_t>([&]() -> Result<std::uint32_t> {
    LMCFG_ASSIGN_OR_RETURN(auto s, id_value(setup, 0x85, true, opt_.timeout));
    if (s.key != entry) {
      return Error(Errc::unexpected_response, "CT setup read of entry " + std::to_string(entry) +
                                                  " answered for entry " + std::to_string(s.key));
    }
    return s.value;
  });
  if (!size.ok()) {
    if (!probe_refusal(size.error())) return std::move(size).error();
    // An error state for the entry query: nothing there (§12 leaves the answer open).
    if (!forms_.empty_ct_entry)
      forms_.empty_ct_entry = static_cast<std::uint8_t>(size.error().code.value());
    return std::optional<Bytes>();
  }
  if (*size == 0) {
    if (!forms_.empty_ct_entry) forms_.empty_ct_entry = state::ok;
    return std::optional<Bytes>();
  }
  if (*size > 0xFFFF) {
    return Error(Errc::unexpected_response,
                 "CT entry " + std::to_string(entry) + " has size " + std::to_string(*size));
  }
  LMCFG_ASSIGN_OR_RETURN(
      auto bytes, read_block(setup, 0x85, make_ct(opt_.id, CtOp::read_data, entry), 0x86, *size,
                             ("command table entry " + std::to_string(entry)).c_str()));
  return std::optional<Bytes>(std::move(bytes));
}

Result<Bytes> LinrsClient::read_ct_entry(std::uint16_t entry) {
  LMCFG_ASSIGN_OR_RETURN(auto got, probe_ct_entry(entry));
  if (!got) {
    return Error(Errc::unexpected_response,
                 "CT entry " + std::to_string(entry) + " has size 0 (not defined?)");
  }
  return std::move(*got);
}

Result<void> LinrsClient::write_ct_entry(std::uint16_t entry, ByteView bytes) {
  const std::string name = "command table entry " + std::to_string(entry);
  RestartBudget budget(opt_.read_retries + 1, opt_.transfer_deadline);
  for (int pass_no = 0;; ++pass_no) {
    WritePass pass;
    if (pass_no > 0) ++stats_.block_rewrites;
    // The setup telegram (re)creates the entry with its size (§12).
    auto setup =
        id_value(make_ct_setup_write(opt_.id, entry, static_cast<std::uint32_t>(bytes.size())),
                 0x83, false, opt_.timeout);
    if (!setup.ok()) {
      if (!is_link_error(setup.error())) return std::move(setup).error();
      pass.lost_answers = true;
    }
    write_chunks(bytes, name, pass, [&](std::array<std::uint8_t, 4> c) {
      return id_value(make_ct_write(opt_.id, entry, c), 0x84, false, opt_.timeout);
    });
    auto done = settle_write_pass(
        pass, budget, name,
        [&]() -> Result<std::optional<bool>> {
          LMCFG_ASSIGN_OR_RETURN(auto back, probe_ct_entry(entry));
          if (!back) return std::optional<bool>{};
          return std::optional<bool>{*back == Bytes(bytes.begin(), bytes.end())};
        },
        stats_.writes_confirmed);
    if (done) return std::move(*done);
  }
}

Result<void> LinrsClient::delete_ct_entry(std::uint16_t entry) {
  LMCFG_TRY(id_value(make_ct(opt_.id, CtOp::delete_one, entry), 0x82, false, opt_.timeout));
  return {};
}
Result<void> LinrsClient::delete_all_ct() {
  LMCFG_TRY(id_value(make_ct(opt_.id, CtOp::delete_all), 0x81, false, opt_.timeout));
  return {};
}
Result<void> LinrsClient::save_ct() {
  LMCFG_ASSIGN_OR_RETURN(auto t,
                         transact_long(make_ct(opt_.id, CtOp::save_to_flash), opt_.flash_timeout,
                                       "saving the command table to flash"));
  LMCFG_TRY(decode_id_value(t, 0x80));
  return {};
}

}  // namespace lmcfg::client
