// The UPID database for Python: parameters, error codes.
#include <pybind11/stl.h>

#include "bindings.hpp"
#include "common/bytes.hpp"
#include "common/types.hpp"
#include "db/database.hpp"

namespace lmcfg::python {

void bind_database(py::module_& m) {
  // --- database ------------------------------------------------------------
  py::class_<db::Parameter>(m, "DbParameter", "A UPID as the UPID database describes it.")
      .def_readonly("upid", &db::Parameter::upid)
      .def_readonly("name", &db::Parameter::name)
      .def_readonly("path", &db::Parameter::path)
      .def_readonly("description", &db::Parameter::description)
      .def_readonly("comm", &db::Parameter::comm)
      .def_readonly("default", &db::Parameter::default_value)
      .def_property_readonly(
          "layer", [](const db::Parameter& p) { return std::string(db::layer_name(p.layer)); })
      .def_property_readonly("unit", [](const db::Parameter& p) { return p.spec.unit; })
      .def_property_readonly("scale", [](const db::Parameter& p) { return p.spec.scale; })
      .def_property_readonly("min", [](const db::Parameter& p) { return p.spec.min; })
      .def_property_readonly("max", [](const db::Parameter& p) { return p.spec.max; })
      .def_property_readonly("type",
                             [](const db::Parameter& p) -> std::optional<std::string> {
                               if (!p.spec.type) return std::nullopt;
                               return std::string(type_name(*p.spec.type));
                             })
      .def_property_readonly("labels",
                             [](const db::Parameter& p) {
                               std::map<std::int64_t, std::string> out;
                               for (const auto& l : p.spec.labels) out[l.raw] = l.label;
                               return out;
                             })
      .def(
          "format", [](const db::Parameter& p, std::uint32_t raw) { return p.format(raw); },
          py::arg("raw"), "A raw value for people: scaled with unit, or its enum label.")
      .def("__repr__", [](const db::Parameter& p) {
        return "<DbParameter " + hex(p.upid, 4) + "h " + p.name + ">";
      });

  py::class_<db::ErrorEntry>(m, "DbError", "An error code as the UPID database describes it.")
      .def_readonly("domain", &db::ErrorEntry::domain)
      .def_readonly("code", &db::ErrorEntry::code)
      .def_readonly("text", &db::ErrorEntry::text)
      .def_readonly("description", &db::ErrorEntry::description)
      .def_readonly("action", &db::ErrorEntry::action)
      .def_readonly("error_class", &db::ErrorEntry::error_class);

  py::class_<db::Database>(m, "Database",
                           "The UPID database (names, units, types, ranges, labels, error "
                           "texts). An empty one finds nothing.")
      .def(py::init<>(), "An empty database.")
      .def_static(
          "open", [](const std::string& path) { return value_or_raise(db::Database::open(path)); },
          py::arg("path"), "Opens a compiled database (lmcfg-upid.sqlite).")
      .def_property_readonly("is_empty", &db::Database::is_empty)
      .def_property_readonly("path", [](const db::Database& d) { return d.info().path; })
      .def_property_readonly("content_hash",
                             [](const db::Database& d) { return d.info().content_hash; })
      .def(
          "find",
          [](const db::Database& d, std::uint16_t upid) -> std::optional<db::Parameter> {
            const auto* p = d.find(upid);
            if (!p) return std::nullopt;
            return *p;
          },
          py::arg("upid"), "The UPID's description, or None when the database does not know it.")
      .def(
          "parameter",
          [](const db::Database& d, std::uint16_t upid) {
            const auto* p = d.find(upid);
            if (!p)
              throw py::key_error("UPID " + hex(upid, 4) + "h is not in the UPID database" +
                                  (d.is_empty() ? " (no database loaded)" : ""));
            return *p;
          },
          py::arg("upid"), "The UPID's description; KeyError when the database does not know it.")
      .def(
          "search",
          [](const db::Database& d, const std::string& needle) {
            std::vector<db::Parameter> out;
            for (const auto* p : d.search(needle)) out.push_back(*p);
            return out;
          },
          py::arg("text"),
          "Parameters whose name, tree path or description contains `text` (case-insensitive).")
      .def(
          "error",
          [](const db::Database& d, const std::string& domain,
             std::uint32_t code) -> std::optional<db::ErrorEntry> {
            const auto* e = d.error(domain, code);
            if (!e) return std::nullopt;
            return *e;
          },
          py::arg("domain"), py::arg("code"),
          "An error code's entry ('mc', 'linrs', 'devicenet'), or None.");
}

}  // namespace lmcfg::python
