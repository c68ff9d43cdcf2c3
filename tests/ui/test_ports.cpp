// The connect page's list of serial ports (ui/ports.hpp) on a tree of its
// own: /dev/serial/by-id names, sysfs USB descriptors, a port held by
// another program.
#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>

#include "files.hpp"
#include "ui/ports.hpp"

namespace ui_test_ports {

using namespace lmcfg;
namespace fs = std::filesystem;

void write(const fs::path& p, const std::string& text) {
  fs::create_directories(p.parent_path());
  std::ofstream(p) << text << "\n";
}

#ifndef _WIN32
TEST_CASE("ports: by-id names with the adapter's USB descriptors, then bare ttys", "[ui_ports]") {
  test::ScratchDir dir("ui-ports");
  ui::PortRoots roots{dir.path / "dev", dir.path / "sys", dir.path / "proc"};
  write(roots.dev / "ttyUSB0", "");
  write(roots.dev / "ttyACM3", "");
  fs::create_directories(roots.dev / "serial" / "by-id");
  fs::create_symlink("../../ttyUSB0", roots.dev / "serial" / "by-id" /
                                          "usb-FTDI_FT232R_USB_UART_A10K1XYZ-if00-port0");
  const fs::path usb = roots.sys / "devices" / "pci0" / "usb1" / "1-1";
  write(usb / "idVendor", "0403");
  write(usb / "idProduct", "6001");
  write(usb / "manufacturer", "FTDI");
  write(usb / "product", "FT232R USB UART");
  write(usb / "serial", "A10K1XYZ");
  fs::create_directories(usb / "1-1:1.0" / "ttyUSB0");
  fs::create_directories(roots.sys / "class" / "tty" / "ttyUSB0");
  fs::create_symlink(usb / "1-1:1.0" / "ttyUSB0",
                     roots.sys / "class" / "tty" / "ttyUSB0" / "device");
  // ttyACM3 is held by another program.
  write(roots.proc / "77" / "comm", "minicom");
  fs::create_directories(roots.proc / "77" / "fd");
  fs::create_symlink(roots.dev / "ttyACM3", roots.proc / "77" / "fd" / "3");

  const auto ports = ui::list_ports(roots);
  REQUIRE(ports.size() == 2);
  CHECK(ports[0].port ==
        (roots.dev / "serial/by-id/usb-FTDI_FT232R_USB_UART_A10K1XYZ-if00-port0").string());
  CHECK(ports[0].device == fs::canonical(roots.dev / "ttyUSB0").string());
  CHECK(ports[0].vendor_id == "0403");
  CHECK(ports[0].product_id == "6001");
  CHECK(ports[0].description == "FTDI FT232R USB UART, serial A10K1XYZ");
  CHECK(ports[0].held_by.empty());
  // ttyUSB0 is listed once, under its by-id name; ttyACM3 has none.
  CHECK(ports[1].port == (roots.dev / "ttyACM3").string());
  CHECK(ports[1].description.empty());
  CHECK(ports[1].held_by == "minicom (PID 77)");
}

TEST_CASE("ports: no adapter, no list, and a dangling by-id name is left out", "[ui_ports]") {
  test::ScratchDir dir("ui-ports-none");
  ui::PortRoots roots{dir.path / "dev", dir.path / "sys", dir.path / "proc"};
  CHECK(ui::list_ports(roots).empty());
  fs::create_directories(roots.dev / "serial" / "by-id");
  fs::create_symlink("../../ttyUSB9", roots.dev / "serial" / "by-id" / "usb-gone");
  CHECK(ui::list_ports(roots).empty());
}
#endif

}  // namespace ui_test_ports
