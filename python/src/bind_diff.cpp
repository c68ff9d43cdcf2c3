// lmcfg.diff() and lmcfg.diff_text(): the comparison `lmcfg diff` makes.
#include <pybind11/stl.h>

#include "bindings.hpp"
#include "db/database.hpp"
#include "ops/diff.hpp"

namespace lmcfg::python {

namespace {

// Two files: a default neither the database nor a file records stays unknown
// (the tool asks a connected drive only when a side is `drive`).
std::optional<std::uint32_t> no_default(std::uint16_t) { return std::nullopt; }

}  // namespace

void bind_diff(py::module_& m) {
  // --- diff ----------------------------------------------------------------
  py::class_<ops::DiffItem>(m, "DiffItem", "One difference, as `lmcfg diff --json` lists it.")
      .def_property_readonly("kind", [](const ops::DiffItem& d) { return ops::kind_name(d.kind); })
      .def_readonly("layer", &ops::DiffItem::layer)
      .def_readonly("key", &ops::DiffItem::key,
                    "UPID, curve ID, CT entry ID or DeviceNet command ID")
      .def_property_readonly(
          "upid",
          [](const ops::DiffItem& d) -> std::optional<std::uint32_t> {
            if (d.kind != ops::DiffItem::Kind::parameter) return std::nullopt;
            return d.key;
          },
          "the UPID for a parameter, else None")
      .def_readonly("name", &ops::DiffItem::name)
      .def_readonly("old", &ops::DiffItem::a, "the value on side A, as text")
      .def_readonly("new", &ops::DiffItem::b, "the value on side B, as text")
      .def_readonly("detail", &ops::DiffItem::detail)
      .def_readonly("old_invalid", &ops::DiffItem::a_invalid)
      .def_readonly("new_invalid", &ops::DiffItem::b_invalid)
      .def("__repr__", [](const ops::DiffItem& d) {
        return std::string("<DiffItem ") + ops::kind_name(d.kind) + " " + std::to_string(d.key) +
               " " + d.name + ": " + d.a + " -> " + d.b + ">";
      });
  m.def(
      "diff",
      [](const config::DriveConfig& a, const config::DriveConfig& b, bool ignore_metadata,
         bool ignore_unit, py::object db_arg) {
        py::object db = database_or_default(std::move(db_arg));
        ops::DiffOptions o;
        o.ignore_metadata = ignore_metadata;
        o.ignore_unit = ignore_unit;
        return ops::diff(a, b, db.cast<const db::Database&>(), no_default, o).items;
      },
      py::arg("a"), py::arg("b"), py::arg("ignore_metadata") = false,
      py::arg("ignore_unit") = false, py::arg("db") = py::none(),
      "The differences between two configurations, as `lmcfg diff A B` lists them.");
  m.def(
      "diff_text",
      [](const config::DriveConfig& a, const config::DriveConfig& b, const std::string& a_name,
         const std::string& b_name, bool ignore_metadata, bool ignore_unit, py::object db_arg) {
        py::object db = database_or_default(std::move(db_arg));
        ops::DiffOptions o;
        o.ignore_metadata = ignore_metadata;
        o.ignore_unit = ignore_unit;
        const auto& d = db.cast<const db::Database&>();
        return ops::render_text(ops::diff(a, b, d, no_default, o), a_name, b_name);
      },
      py::arg("a"), py::arg("b"), py::arg("a_name") = "A", py::arg("b_name") = "B",
      py::arg("ignore_metadata") = false, py::arg("ignore_unit") = false,
      py::arg("db") = py::none(), "The difference report `lmcfg diff A B` prints.");
}

}  // namespace lmcfg::python
