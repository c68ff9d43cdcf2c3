#pragma once
// The serial ports of this computer as the connect page lists them (docs/ui.md
// "Connect"): what the adapter says about itself and who holds the port.
// ports.cpp reads Linux's /dev/serial/by-id and sysfs, ports_win32.cpp lists
// the COM ports Windows knows; both behind this one call.
#include <filesystem>
#include <string>
#include <vector>

namespace lmcfg::ui {

struct SerialPortInfo {
  std::string port;    // what --port takes: "/dev/serial/by-id/usb-FTDI_...-port0", "COM3"
  std::string device;  // the device it names: "/dev/ttyUSB0" ("" when the same as port)
  // What the USB adapter reports (sysfs on Linux; "" where unknown).
  std::string vendor_id, product_id;  // "0403", "6001"
  std::string manufacturer, product, serial;
  std::string description;  // one line for people: "FTDI FT232R USB UART, serial A10K1XYZ"
  std::string held_by;      // "lmcfg backup (PID 4242)", "minicom (PID 77)"; "" = free
};

// Where the listing looks (tests point it at a tree of their own).
struct PortRoots {
  std::filesystem::path dev = "/dev";
  std::filesystem::path sys = "/sys";
  std::filesystem::path proc = "/proc";
};

// Sorted by port: on Linux each /dev/serial/by-id name (an adapter by its own
// name), then /dev/ttyUSB* and /dev/ttyACM* that no by-id name covers; on
// Windows the COM ports. Never fails: a port whose details cannot be read is
// listed without them.
std::vector<SerialPortInfo> list_ports(const PortRoots& roots = {});

// Where list_ports looked, for a page that found no port: "under
// /dev/serial/by-id, /dev/ttyUSB* or /dev/ttyACM*" (Windows: "among the COM
// ports Windows knows").
const char* where_ports_are_looked_for();

// The program that has `device` open, from its lock (transport::port_holder)
// or, on Linux, from the processes' open files: "minicom (PID 77)"; "" when
// none is found (another user's process cannot be seen).
std::string port_user(const std::string& device, const PortRoots& roots = {});

}  // namespace lmcfg::ui
