// Configurations for Python: parameters, curves, command table entries, the
// file formats.
#include <pybind11/operators.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include "bindings.hpp"
#include "common/bytes.hpp"
#include "common/layers.hpp"
#include "config/config_io.hpp"
#include "db/database.hpp"
#include "ops/diff.hpp"

namespace lmcfg::python {

namespace {

// ---------------------------------------------------------------------------
// Configurations.
std::optional<config::FileFormat> format_arg(const std::optional<std::string>& name) {
  if (!name) return std::nullopt;
  return value_or_raise(config::format_from_name(*name));
}

config::WriteOptions write_options(const db::Database& db,
                                   std::optional<ops::DatabaseCtDecoder>& decoder) {
  config::WriteOptions wo;
  if (!db.is_empty()) wo.ct_decoder = &decoder.emplace(db);
  return wo;
}

// A parameter of a configuration with the layer it belongs to.
struct LayerParameter {
  int layer = 0;
  config::Parameter p;
};

std::vector<LayerParameter> parameters_of(const config::DriveConfig& c) {
  std::vector<LayerParameter> out;
  for (std::size_t i = 0; i < c.layers.size(); ++i)
    for (const auto& p : c.layers[i]) out.push_back({static_cast<int>(i + 1), p});
  return out;
}

py::bytes bytes_of(const Bytes& b) {
  return py::bytes(reinterpret_cast<const char*>(b.data()), b.size());
}

std::string layer_name(int layer) { return std::string(layers::name(layer)); }

// A configuration's values: parameters with their layer, curves, command table entries.
void bind_config_values(py::module_& m) {
  py::class_<LayerParameter>(m, "Parameter", "One parameter value of a configuration.")
      .def_readonly("layer", &LayerParameter::layer, "1 OS, 2 MC, 3 Intf, 4 Appl")
      .def_property_readonly("layer_name",
                             [](const LayerParameter& p) { return layer_name(p.layer); })
      .def_property_readonly("upid", [](const LayerParameter& p) { return p.p.upid; })
      .def_property_readonly(
          "value", [](const LayerParameter& p) { return p.p.value; }, "the raw 4-byte value field")
      .def_property_readonly("type", [](const LayerParameter& p) { return p.p.type; })
      .def_property_readonly("default", [](const LayerParameter& p) { return p.p.default_value; })
      .def_property_readonly("name", [](const LayerParameter& p) { return p.p.name; })
      .def_property_readonly("unit", [](const LayerParameter& p) { return p.p.unit; })
      .def_property_readonly("scaled", [](const LayerParameter& p) { return p.p.scaled; })
      .def("__repr__", [](const LayerParameter& p) {
        return "<Parameter " + hex(p.p.upid, 4) + "h " + p.p.name + " = " +
               std::to_string(p.p.value) + ">";
      });

  py::class_<config::Curve>(m, "Curve", "A motion curve (info and data block as read, §11).")
      .def_readonly("id", &config::Curve::id)
      .def_property_readonly("info", [](const config::Curve& c) { return bytes_of(c.info); })
      .def_property_readonly("data", [](const config::Curve& c) { return bytes_of(c.data); });
  py::class_<config::CtEntry>(m, "CtEntry", "A command table entry (raw bytes, §12).")
      .def_readonly("id", &config::CtEntry::id)
      .def_property_readonly("raw", [](const config::CtEntry& e) { return bytes_of(e.raw); });
}

void bind_config_class(py::module_& m) {
  py::class_<config::DriveConfig>(
      m, "Config", "A drive configuration: parameters, curves, command table, identity.")
      .def(py::init<>())
      .def_static(
          "load",
          [](const std::filesystem::path& path, std::optional<std::string> format) {
            return value_or_raise(config::read_config_file(path, format_arg(format)));
          },
          py::arg("path"), py::arg("format") = py::none(),
          "Reads a JSON or XML file (format from the extension, else the content).")
      .def_static(
          "loads",
          [](const std::string& text, std::string format, std::string name) {
            return value_or_raise(config::read_config_text(text, name, *format_arg(format)));
          },
          py::arg("text"), py::arg("format") = "json", py::arg("name") = "<string>",
          "Parses JSON or XML text.")
      .def(
          "save",
          [](const config::DriveConfig& c, const std::filesystem::path& path,
             std::optional<std::string> format, py::object db_arg) {
            py::object db = database_or_default(std::move(db_arg));
            std::optional<ops::DatabaseCtDecoder> decoder;
            ok_or_raise(
                config::write_config_file(c, path, format_arg(format),
                                          write_options(db.cast<const db::Database&>(), decoder)));
          },
          py::arg("path"), py::arg("format") = py::none(), py::arg("db") = py::none(),
          "Writes the file atomically (format from the extension unless given).")
      .def(
          "dumps",
          [](const config::DriveConfig& c, std::string format, py::object db_arg) {
            py::object db = database_or_default(std::move(db_arg));
            std::optional<ops::DatabaseCtDecoder> decoder;
            return value_or_raise(config::write_config_text(
                c, *format_arg(format), write_options(db.cast<const db::Database&>(), decoder)));
          },
          py::arg("format") = "json", py::arg("db") = py::none(), "The canonical text of the file.")
      .def_property_readonly("parameters", &parameters_of)
      .def(
          "parameter",
          [](const config::DriveConfig& c, std::uint16_t upid) -> std::optional<LayerParameter> {
            const auto* p = c.find_param(upid);
            if (!p) return std::nullopt;
            return LayerParameter{layers::of_upid(upid), *p};
          },
          py::arg("upid"), "The parameter with this UPID, or None.")
      .def_readonly("curves", &config::DriveConfig::curves)
      .def_readonly("ct_entries", &config::DriveConfig::ct_entries)
      .def_property_readonly("macid", [](const config::DriveConfig& c) { return c.identity.macid; })
      .def_property_readonly("firmware",
                             [](const config::DriveConfig& c) { return c.identity.firmware; })
      .def_property_readonly("captured_at",
                             [](const config::DriveConfig& c) { return c.identity.captured_at; })
      .def_property_readonly("port",
                             [](const config::DriveConfig& c) { return c.identity.link.port; })
      .def_property(
          "labels", [](const config::DriveConfig& c) { return c.identity.labels; },
          [](config::DriveConfig& c, std::map<std::string, std::string> l) {
            c.identity.labels = std::move(l);
          })
      .def_property_readonly(
          "full",
          [](const config::DriveConfig& c) { return c.scope.parameters == config::ParamSet::full; })
      .def(py::self == py::self)
      .def("__repr__", [](const config::DriveConfig& c) {
        std::size_t n = 0;
        for (const auto& l : c.layers) n += l.size();
        return "<Config MACID " + c.identity.macid + ": " + std::to_string(n) + " parameters, " +
               std::to_string(c.curves.size()) + " curves, " + std::to_string(c.ct_entries.size()) +
               " CT entries>";
      });
}

}  // namespace

void bind_config(py::module_& m) {
  bind_config_values(m);
  bind_config_class(m);
}

}  // namespace lmcfg::python
