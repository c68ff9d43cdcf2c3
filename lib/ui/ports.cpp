// Linux: USB serial adapters by /dev/serial/by-id (udev's names, made from
// the adapter's vendor, product and serial number) and their USB descriptors
// in sysfs (/sys/class/tty/NAME/device, up to the USB device with idVendor).
#include "ui/ports.hpp"

#include <algorithm>
#include <fstream>
#include <set>
#include <system_error>

#include "transport/transport.hpp"

namespace lmcfg::ui {

namespace fs = std::filesystem;

namespace {

std::string first_line(const fs::path& p) {
  std::ifstream in(p);
  std::string s;
  std::getline(in, s);
  while (!s.empty() && (s.back() == '\r' || s.back() == ' ')) s.pop_back();
  return s;
}

// The USB device above a tty's interface: the first parent with idVendor.
void usb_details(const fs::path& sys, const std::string& name, SerialPortInfo& out) {
  std::error_code ec;
  fs::path dev = fs::canonical(sys / "class" / "tty" / name / "device", ec);
  if (ec) return;
  for (int up = 0; up < 4 && !dev.empty() && dev != dev.root_path();
       ++up, dev = dev.parent_path()) {
    if (!fs::exists(dev / "idVendor", ec)) continue;
    out.vendor_id = first_line(dev / "idVendor");
    out.product_id = first_line(dev / "idProduct");
    out.manufacturer = first_line(dev / "manufacturer");
    out.product = first_line(dev / "product");
    out.serial = first_line(dev / "serial");
    return;
  }
}

std::string describe(const SerialPortInfo& p) {
  std::string d = p.manufacturer;
  if (!p.product.empty()) d += (d.empty() ? "" : " ") + p.product;
  if (d.empty() && !p.vendor_id.empty()) d = "USB " + p.vendor_id + ":" + p.product_id;
  if (!p.serial.empty()) d += (d.empty() ? "serial " : ", serial ") + p.serial;
  return d;
}

bool tty_usb_name(const std::string& n) {
  return n.rfind("ttyUSB", 0) == 0 || n.rfind("ttyACM", 0) == 0;
}

}  // namespace

std::string port_user(const std::string& device, const PortRoots& roots) {
  if (auto h = transport::port_holder(device))
    return (h->holder.empty() ? "a program" : h->holder) + " (PID " + std::to_string(h->pid) + ")";
  std::error_code ec;
  const fs::path target = fs::weakly_canonical(device, ec);
  if (ec) return "";
  // Another program (minicom, the vendor's tool under Wine): a process whose
  // open files include the device. Only this user's processes are readable.
  for (fs::directory_iterator it(roots.proc, ec), end; !ec && it != end; it.increment(ec)) {
    const std::string pid = it->path().filename().string();
    if (pid.empty() || pid.find_first_not_of("0123456789") != std::string::npos) continue;
    std::error_code fd_ec;
    for (fs::directory_iterator fd(it->path() / "fd", fd_ec), fend; !fd_ec && fd != fend;
         fd.increment(fd_ec)) {
      std::error_code link_ec;
      if (fs::read_symlink(fd->path(), link_ec) != target || link_ec) continue;
      const std::string comm = first_line(it->path() / "comm");
      return (comm.empty() ? "a program" : comm) + " (PID " + pid + ")";
    }
  }
  return "";
}

const char* where_ports_are_looked_for() {
  return "under /dev/serial/by-id, /dev/ttyUSB* or /dev/ttyACM*";
}

std::vector<SerialPortInfo> list_ports(const PortRoots& roots) {
  std::vector<SerialPortInfo> out;
  std::set<std::string> covered;  // devices a by-id name lists
  std::error_code ec;
  for (fs::directory_iterator it(roots.dev / "serial" / "by-id", ec), end; !ec && it != end;
       it.increment(ec)) {
    SerialPortInfo p;
    p.port = it->path().string();
    std::error_code link_ec;
    const fs::path dev = fs::canonical(it->path(), link_ec);
    if (link_ec) continue;  // a dangling name: the adapter is being unplugged
    p.device = dev.string();
    covered.insert(p.device);
    usb_details(roots.sys, dev.filename().string(), p);
    out.push_back(std::move(p));
  }
  for (fs::directory_iterator it(roots.dev, ec), end; !ec && it != end; it.increment(ec)) {
    const std::string name = it->path().filename().string();
    if (!tty_usb_name(name)) continue;
    std::error_code c_ec;
    const std::string dev = fs::canonical(it->path(), c_ec).string();
    if (c_ec || covered.count(dev)) continue;
    SerialPortInfo p;
    p.port = it->path().string();
    usb_details(roots.sys, name, p);
    out.push_back(std::move(p));
  }
  for (auto& p : out) {
    p.description = describe(p);
    p.held_by = port_user(p.device.empty() ? p.port : p.device, roots);
  }
  std::sort(out.begin(), out.end(),
            [](const SerialPortInfo& a, const SerialPortInfo& b) { return a.port < b.port; });
  return out;
}

}  // namespace lmcfg::ui
