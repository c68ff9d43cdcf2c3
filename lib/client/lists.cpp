// Parameter lists (LinRS §10.2, §10.3).
//
// A list is read in passes from its start telegram ("get next" advances the
// drive's cursor, so a pass that loses an answer restarts from the start). The
// passes go on while they make progress (RestartBudget). Where nothing on the
// link detects a flipped bit (agreeing_reads() > 1), a list counts only when
// that many complete passes are identical.
#include <algorithm>
#include <cstdio>

#include "client/client.hpp"
#include "client/internal.hpp"
#include "common/layers.hpp"

namespace lmcfg::client {

using namespace codec;
using detail::hexid;
using detail::is_link_error;
using detail::RestartBudget;

namespace {
bool restartable(const Error& e) { return is_link_error(e) || e.code == ErrorClass::drive_refusal; }
}  // namespace

struct LinrsClient::ModifiedPass {
  std::vector<ModifiedParam> params;
  // Ended with a C6 whose UPID is no modified parameter of the layer: an
  // empty list's end, or the "no list" answer of a drive that lost its cursor.
  std::optional<std::string> odd_end;
};

Result<std::vector<ModifiedParam>> LinrsClient::modified_list(int layer) {
  const std::uint16_t base = lmcfg::layers::base_upid(layer);
  const std::string lname(lmcfg::layers::name(layer));
  // Failures allowed per position: twice the read attempts of a single value.
  RestartBudget budget(2 * (opt_.read_retries + 1), opt_.transfer_deadline);
  std::vector<std::vector<ModifiedParam>> complete;  // passes that ended with C6
  Error last(Errc::timeout, "");
  for (;;) {
    std::size_t reached = 0;
    ModifiedPass pass;
    auto start = cfg(CfgOp::start_modified, base, true, opt_.timeout);
    if (!start.ok()) {
      if (!restartable(start.error())) return std::move(start).error();
      last = std::move(start).error();
      if (!budget.another_at(0)) break;
      continue;
    }
    LMCFG_ASSIGN_OR_RETURN(std::optional<Error> failed, modified_pass(layer, pass, reached));
    if (!failed) {
      if (auto voted = vote_modified(complete, pass, lname)) return std::move(*voted);
      if (budget.out_of_time()) break;
      continue;
    }
    // A refusal of "get next" in the middle of a list is restartable too: on a
    // link without checksum it is most likely a flipped state byte (C6 -> C4).
    if (!restartable(*failed)) return std::move(*failed);
    last = std::move(*failed);
    if (!budget.another_at(reached)) break;
    ++stats_.retries;
  }
  if (budget.passes() > 1)
    last.message += " (after " + std::to_string(budget.passes()) + " passes)";
  last.message = "modified list of layer " + lname + ": " + last.message;
  return last;
}

Result<std::optional<Error>> LinrsClient::modified_pass(int layer, ModifiedPass& pass,
                                                        std::size_t& reached) {
  const std::uint16_t base = lmcfg::layers::base_upid(layer);
  for (std::size_t guard = 0;; ++guard) {
    if (guard > 0x0F00) {
      return Error(Errc::unexpected_response, "modified list of layer " +
                                                  std::string(lmcfg::layers::name(layer)) +
                                                  " did not end (no C6 after 3840 entries)");
    }
    // §10.2 sends the layer base with "get next" in one example and 0000 in another (erratum).
    auto next = cfg(CfgOp::next_modified, base, false, opt_.timeout);
    if (!next.ok()) return std::optional<Error>(std::move(next).error());
    reached = pass.params.size() + 1;
    const bool last_one = next->state == state::last_in_list;
    const bool in_layer = lmcfg::layers::of_upid(next->key) == layer;
    const bool seen = !pass.params.empty() && pass.params.back().upid == next->key;
    if (!last_one) {
      if (!in_layer) {
        // A garbled answer (no checksum) or a drive that is not where we
        // think: the pass fails and the list restarts.
        return std::optional<Error>(
            Error(Errc::unexpected_response,
                  "returned UPID " + hexid("%04Xh", next->key) + " outside the layer's range"));
      }
      pass.params.push_back({next->key, next->value});
      continue;
    }
    // C6 ends the list; its UPID counts once, only if it lies in the layer
    // and was not already received (§10.2 vs §10.3, a seed erratum). A drive may end an empty list
    // with a UPID of the layer that is no modified parameter (e.g. 0000h, or
    // the UPID of the request): when the C6 is the first answer or names the
    // requested UPID, it counts only if the drive's default differs from it.
    if (in_layer && !seen) {
      bool modified = true;
      if (next->key == base || next->key == 0x0000) {
        auto def = unless_refused(get_default(next->key));
        if (!def.ok()) return std::optional<Error>(std::move(def).error());
        modified = def->has_value() && **def != next->value;
      }
      if (modified) {
        pass.params.push_back({next->key, next->value});
      } else {
        pass.odd_end = "ended with C6 for UPID " + hexid("%04Xh", next->key) + " = " +
                       std::to_string(next->value) + ", which is no modified parameter";
      }
    } else if (!in_layer) {
      pass.odd_end = "ended with C6 for UPID " + hexid("%04Xh", next->key) +
                     " outside the layer (drive lost the list cursor?)";
    }
    return std::optional<Error>();
  }
}

std::optional<Result<std::vector<ModifiedParam>>> LinrsClient::vote_modified(
    std::vector<std::vector<ModifiedParam>>& complete, ModifiedPass& pass,
    const std::string& lname) {
  // Agreement: agreeing_reads() identical passes; an odd end is confirmed
  // by a second pass ending the same way (confirm_empty_lists).
  int need = agreeing_reads();
  if (pass.odd_end && (!pass.params.empty() || opt_.confirm_empty_lists)) need = std::max(need, 2);
  // An empty list and a drive that reset between "start" and the first
  // "get next" answer alike (C6 with a UPID outside the layer), and two
  // resets at that point in a row are rare but happen on a line with
  // power dips (docs/reliability.md, soak): a third pass makes the wrong
  // empty list need three in a row.
  if (pass.odd_end && pass.params.empty() && opt_.confirm_empty_lists) need = std::max(need, 3);
  int count = 1;
  for (const auto& c : complete) {
    count += c == pass.params ? 1 : 0;
    if (!(c == pass.params)) noise_seen_ = true;
  }
  need = std::max(need, agreeing_reads());
  if (count >= need) {
    if (static_cast<int>(complete.size()) + 1 > need) ++stats_.disagreements;
    return Result<std::vector<ModifiedParam>>(std::move(pass.params));
  }
  complete.push_back(pass.params);
  if (pass.odd_end && need > agreeing_reads() && complete.size() == 1) {
    ++stats_.retries;
  } else {
    ++stats_.extra_reads;
  }
  if (static_cast<int>(complete.size()) >= need + 2 + opt_.read_retries) {
    ++stats_.disagreements;
    return Result<std::vector<ModifiedParam>>(
        Error(Errc::unexpected_response,
              "modified list of layer " + lname + ": " + std::to_string(complete.size()) +
                  " complete reads, no " + std::to_string(need) + " of them agree" +
                  (pass.odd_end ? " (last one " + *pass.odd_end + ")" : std::string())));
  }
  return std::nullopt;
}

Result<std::vector<UpidInfo>> LinrsClient::upid_list(
    int layer, const std::function<void(std::size_t)>& progress) {
  const std::uint16_t base = lmcfg::layers::base_upid(layer);
  // Failures allowed per position: twice the read attempts of a single value.
  RestartBudget budget(2 * (opt_.read_retries + 1), opt_.transfer_deadline);
  std::vector<std::vector<UpidInfo>> complete;
  Error last(Errc::timeout, "");
  for (;;) {
    auto start = cfg(CfgOp::start_upid_list, base, true, opt_.timeout);
    if (!start.ok()) {
      if (!restartable(start.error())) return std::move(start).error();
      last = std::move(start).error();
      if (!budget.another_at(0)) break;
      continue;
    }
    std::vector<UpidInfo> out;
    std::optional<Error> failed;
    bool ended = false;
    for (std::size_t guard = 0; guard <= 0x0F00; ++guard) {
      auto t = transact(make_cfg(opt_.id, CfgOp::next_upid, base), opt_.timeout, false);
      if (!t.ok()) {
        failed = std::move(t).error();
        break;
      }
      auto e = decode_upid_list_entry(*t);
      if (!e.ok()) return std::move(e).error();
      const bool last_one = e->state == state::last_in_list;
      const bool in_layer = lmcfg::layers::of_upid(e->upid) == layer;
      const bool seen = !out.empty() && out.back().upid == e->upid;
      if ((!last_one || !seen) && in_layer) out.push_back({e->upid, e->address_usage, e->type});
      if (progress) progress(out.size());
      if (last_one) {
        ended = true;
        break;
      }
    }
    if (!failed && !ended)
      return Error(Errc::unexpected_response, "UPID list did not end (no C6 after 3840 entries)");
    if (!failed) {
      int count = 1;
      for (const auto& c : complete) {
        count += c == out ? 1 : 0;
        if (!(c == out)) noise_seen_ = true;
      }
      const int need = agreeing_reads();
      if (count >= need) {
        if (static_cast<int>(complete.size()) + 1 > need) ++stats_.disagreements;
        return out;
      }
      complete.push_back(std::move(out));
      ++stats_.extra_reads;
      if (static_cast<int>(complete.size()) >= need + 2 + opt_.read_retries) {
        ++stats_.disagreements;
        return Error(Errc::unexpected_response,
                     "UPID list of layer " + std::string(lmcfg::layers::name(layer)) + ": " +
                         std::to_string(complete.size()) + " complete reads, no " +
                         std::to_string(need) + " of them agree");
      }
      if (budget.out_of_time()) break;
      continue;
    }
    if (!restartable(*failed)) return std::move(*failed);
    const std::size_t reached = out.size() + 1;
    last = std::move(*failed);
    if (!budget.another_at(reached)) break;
    ++stats_.retries;
  }
  if (budget.passes() > 1)
    last.message += " (after " + std::to_string(budget.passes()) + " passes)";
  return last;
}

}  // namespace lmcfg::client
