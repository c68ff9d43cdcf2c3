// lmcfg.Drive: backup, restore plan, restore, close.
#include <pybind11/stl.h>

#include "drive.hpp"

namespace lmcfg::python {

void bind_drive(py::module_& m) {
  // --- drives ----------------------------------------------------------------
  py::class_<Drive>(m, "Drive",
                    "An open link to one drive. Use it as a context manager: leaving the block "
                    "closes the link (a sim: drive saves its state file).")
      .def(
          "backup",
          [](Drive& d, std::vector<std::string> layers, bool curves, bool command_table, bool full,
             bool describe, std::map<std::string, std::string> labels, py::object progress) {
            return d.backup(layers, curves, command_table, full, describe, labels,
                            std::move(progress));
          },
          py::arg("layers") = std::vector<std::string>{"os", "mc", "intf", "appl"},
          py::arg("curves") = true, py::arg("command_table") = true, py::arg("full") = false,
          py::arg("describe") = true, py::arg("labels") = std::map<std::string, std::string>{},
          py::arg("progress") = py::none(),
          "Reads the drive's configuration (read telegrams only), as `lmcfg backup`.")
      .def("plan_restore", &Drive::plan_restore, py::arg("config"), py::arg("default_first") = true,
           py::arg("include_comm") = false, py::arg("progress") = py::none(),
           "The restore plan for `config` on this drive (reads only). A plan with problems "
           "is returned, not raised: see `.ok` and `.problems`.")
      .def("restore", &Drive::restore, py::arg("config"), py::arg("yes") = false,
           py::arg("confirm") = py::none(), py::arg("dry_run") = false,
           py::arg("default_first") = true, py::arg("include_comm") = false,
           py::arg("reset") = true, py::arg("recovery") = true, py::arg("progress") = py::none(),
           "Plans, writes what differs and verifies, as `lmcfg restore`.")
      .def("close", &Drive::close, "Closes the link (a sim: drive saves its state file).")
      .def_property_readonly("port", &Drive::port)
      .def_property_readonly("describe", [](Drive& d) { return d.session().describe(); })
      .def_property_readonly(
          "telegrams", [](Drive& d) { return d.session().client().stats().requests; },
          "requests sent since the link opened")
      .def("__enter__", [](py::object self) { return self; })
      .def("__exit__", [](Drive& d, py::args) {
        d.close();
        return false;
      });
}

}  // namespace lmcfg::python
