// Restore: whether the target still reads as a plan found it (target_change,
// restore.hpp). The plan's reads are the comparison: no second kind of read.
// This is identity of two reads of one drive (its answers as they came), not a
// comparison of two configurations: no default stands for an unlisted UPID and
// nothing is decoded, so the comparison engine (compare.hpp) does not apply.
#include "common/bytes.hpp"
#include "common/layers.hpp"
#include "ops/restore.hpp"

namespace lmcfg::ops {

namespace {

bool same_curve(const TargetSeen::CurveSeen& a, const TargetSeen::CurveSeen& b) {
  if (a.id != b.id || a.info != b.info || a.data_size != b.data_size) return false;
  // A data block only one of the plans read (it did not need the other) says nothing.
  return !a.data || !b.data || *a.data == *b.data;
}

bool same_step(const PlanStep& a, const PlanStep& b) {
  return a.action == b.action && a.layer == b.layer && a.key == b.key && a.value == b.value &&
         a.old_value == b.old_value;
}

}  // namespace

std::string target_change(const Plan& planned, const Plan& now) {
  std::vector<std::string> what;
  for (std::size_t i = 0; i < planned.target.layers.size(); ++i) {
    if (planned.target.layers[i] != now.target.layers[i])
      what.push_back(std::string("the ") + std::string(layers::name(static_cast<int>(i) + 1)) +
                     " layer's modified parameters");
  }
  if (planned.target.ct_entries != now.target.ct_entries) what.push_back("the command table");
  const auto& ca = planned.target.curves;
  const auto& cb = now.target.curves;
  bool curves_same = ca.has_value() == cb.has_value();
  if (curves_same && ca) {
    curves_same = ca->size() == cb->size();
    for (std::size_t i = 0; curves_same && i < ca->size(); ++i)
      curves_same = same_curve((*ca)[i], (*cb)[i]);
  }
  if (!curves_same) what.push_back("the curves");
  if (what.empty()) {
    bool steps_same = planned.steps.size() == now.steps.size() && planned.ok() == now.ok();
    for (std::size_t i = 0; steps_same && i < planned.steps.size(); ++i)
      steps_same = same_step(planned.steps[i], now.steps[i]);
    if (!steps_same) what.push_back("the values the plan would write over");
  }
  std::string out;
  for (std::size_t i = 0; i < what.size(); ++i)
    out += (i == 0 ? "" : (i + 1 == what.size() ? " and " : ", ")) + what[i];
  return out;
}

}  // namespace lmcfg::ops
