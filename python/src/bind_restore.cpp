// Restore plans and outcomes for Python.
#include <pybind11/stl.h>

#include "bindings.hpp"
#include "ops/recovery.hpp"
#include "ops/restore_run.hpp"

namespace lmcfg::python {

void bind_restore(py::module_& m) {
  // --- restore plan and outcome ----------------------------------------------
  py::class_<ops::PlanStep>(m, "PlanStep", "One step of a restore plan.")
      .def_property_readonly("action",
                             [](const ops::PlanStep& s) { return ops::action_name(s.action); })
      .def_readonly("layer", &ops::PlanStep::layer)
      .def_readonly("key", &ops::PlanStep::key)
      .def_readonly("value", &ops::PlanStep::value)
      .def_readonly("old_value", &ops::PlanStep::old_value)
      .def_readonly("text", &ops::PlanStep::text)
      .def_readonly("name", &ops::PlanStep::name)
      .def_readonly("old", &ops::PlanStep::old_display)
      .def_readonly("new", &ops::PlanStep::new_display)
      .def_property_readonly(
          "why", [](const ops::PlanStep& s) { return ops::write_reason_text(s.reason); })
      .def("__repr__", [](const ops::PlanStep& s) {
        return std::string("<PlanStep ") + ops::action_name(s.action) + ": " + s.text + ">";
      });
  py::class_<ops::Plan>(m, "Plan", "A restore plan: what would be written, and any problems.")
      .def_readonly("problems", &ops::Plan::problems)
      .def_readonly("steps", &ops::Plan::steps)
      .def_readonly("skipped", &ops::Plan::skipped)
      .def_readonly("notes", &ops::Plan::notes)
      .def_readonly("losses", &ops::Plan::losses)
      .def_readonly("write_telegrams", &ops::Plan::write_telegrams)
      .def_property_readonly("ok", &ops::Plan::ok)
      .def_property_readonly("nothing_to_do", &ops::Plan::nothing_to_do)
      .def(
          "json", [](const ops::Plan& p) { return ops::plan_json(p).dump(); },
          "The plan as `lmcfg restore --json` reports it (docs/restore.md), a JSON string.")
      .def("__str__", &ops::render_plan);
  py::class_<ops::RestoreOutcome>(m, "RestoreOutcome", "What a restore did.")
      .def_property_readonly("stage",
                             [](const ops::RestoreOutcome& o) { return ops::stage_name(o.stage); })
      .def_readonly("plan", &ops::RestoreOutcome::plan)
      .def_readonly("mismatches", &ops::RestoreOutcome::mismatches)
      .def_readonly("written", &ops::RestoreOutcome::written)
      .def_property_readonly("link_after",
                             [](const ops::RestoreOutcome& o) -> std::optional<std::string> {
                               if (!o.relink || !o.relink->changed) return std::nullopt;
                               return o.relink->summary;
                             })
      .def("__repr__", [](const ops::RestoreOutcome& o) {
        return std::string("<RestoreOutcome ") + ops::stage_name(o.stage) + ">";
      });
}

}  // namespace lmcfg::python
