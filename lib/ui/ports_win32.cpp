// Windows: the COM ports Windows knows (transport::list_serial_ports,
// QueryDosDevice), each with what its driver says about the adapter. First
// SetupAPI: the devices of the "Ports (COM & LPT)" class, their "PortName"
// (COM5), friendly name ("USB Serial Port (COM5)"), manufacturer and the
// instance ID "USB\VID_0403&PID_6001\A10K1XYZ" (vendor, product and, for an
// adapter with one, its serial number). Where SetupAPI knows no such device
// (Wine maps COM ports to Unix devices without one), the registry's
// HKLM\HARDWARE\DEVICEMAP\SERIALCOMM names the port's kernel device
// ("\Device\Serial0"). A port another program holds says so when it is opened
// ("port COM3 is in use by ..."); lmcfg's own lock is read here.
#ifndef WIN32_LEAN_AND_MEAN
#define WIN32_LEAN_AND_MEAN
#endif
#include <windows.h>
// setupapi.h needs windows.h first.
#include <setupapi.h>

#include <algorithm>
#include <map>

#include "transport/ports.hpp"
#include "transport/transport.hpp"
#include "ui/ports.hpp"

namespace lmcfg::ui {
namespace {

// UTF-16 to UTF-8 (SetupAPI and the registry speak UTF-16).
std::string win_utf8(const std::wstring& w) {
  if (w.empty()) return {};
  const int n = ::WideCharToMultiByte(CP_UTF8, 0, w.data(), static_cast<int>(w.size()), nullptr, 0,
                                      nullptr, nullptr);
  std::string s(static_cast<std::size_t>(n > 0 ? n : 0), '\0');
  if (n > 0)
    ::WideCharToMultiByte(CP_UTF8, 0, w.data(), static_cast<int>(w.size()), s.data(), n, nullptr,
                          nullptr);
  return s;
}

// A REG_SZ from a buffer that may lack its terminating NUL.
std::wstring win_reg_text(const std::vector<wchar_t>& buf, DWORD bytes) {
  std::wstring s(buf.data(), std::min<std::size_t>(buf.size(), bytes / sizeof(wchar_t)));
  while (!s.empty() && s.back() == L'\0') s.pop_back();
  return s;
}

std::string win_device_property(HDEVINFO set, SP_DEVINFO_DATA& dev, DWORD property) {
  std::vector<wchar_t> buf(512);
  DWORD type = 0, bytes = 0;
  if (!::SetupDiGetDeviceRegistryPropertyW(
          set, &dev, property, &type, reinterpret_cast<BYTE*>(buf.data()),
          static_cast<DWORD>(buf.size() * sizeof(wchar_t)), &bytes) ||
      (type != REG_SZ && type != REG_MULTI_SZ))
    return {};
  // A REG_MULTI_SZ (the hardware IDs): its first string.
  return win_utf8(win_reg_text(buf, bytes).c_str());
}

// The text after "KEY_" up to the next '&' or '\' of a USB instance ID.
std::string win_id_part(const std::string& id, const std::string& key) {
  const auto p = id.find(key);
  if (p == std::string::npos) return {};
  const auto start = p + key.size();
  return id.substr(start, id.find_first_of("&\\", start) - start);
}

// The ports class {4D36E978-E325-11CE-BFC1-08002BE10318} (devguid.h's
// GUID_DEVCLASS_PORTS, spelt here so no translation unit must define it).
constexpr GUID kPortsClass = {
    0x4d36e978, 0xe325, 0x11ce, {0xbf, 0xc1, 0x08, 0x00, 0x2b, 0xe1, 0x03, 0x18}};

// What SetupAPI says about each present port, by its name ("COM5").
std::map<std::string, SerialPortInfo> win_setupapi_ports() {
  std::map<std::string, SerialPortInfo> out;
  HDEVINFO set = ::SetupDiGetClassDevsW(&kPortsClass, nullptr, nullptr, DIGCF_PRESENT);
  if (set == INVALID_HANDLE_VALUE) return out;
  SP_DEVINFO_DATA dev{};
  dev.cbSize = sizeof(dev);
  for (DWORD i = 0; ::SetupDiEnumDeviceInfo(set, i, &dev); ++i) {
    HKEY key = ::SetupDiOpenDevRegKey(set, &dev, DICS_FLAG_GLOBAL, 0, DIREG_DEV, KEY_READ);
    if (key == INVALID_HANDLE_VALUE) continue;
    std::vector<wchar_t> buf(64);
    DWORD type = 0, bytes = static_cast<DWORD>(buf.size() * sizeof(wchar_t));
    const bool named =
        ::RegQueryValueExW(key, L"PortName", nullptr, &type, reinterpret_cast<BYTE*>(buf.data()),
                           &bytes) == ERROR_SUCCESS &&
        type == REG_SZ;
    ::RegCloseKey(key);
    if (!named) continue;
    SerialPortInfo p;
    p.port = win_utf8(win_reg_text(buf, bytes));
    p.description = win_device_property(set, dev, SPDRP_FRIENDLYNAME);
    p.manufacturer = win_device_property(set, dev, SPDRP_MFG);
    p.product = win_device_property(set, dev, SPDRP_DEVICEDESC);
    std::vector<wchar_t> id(512);
    if (::SetupDiGetDeviceInstanceIdW(set, &dev, id.data(), static_cast<DWORD>(id.size()),
                                      nullptr)) {
      const std::string instance = win_utf8(id.data());
      p.vendor_id = win_id_part(instance, "VID_");
      p.product_id = win_id_part(instance, "PID_");
      // USB\VID_x&PID_y\SERIAL: the last part is the adapter's serial number
      // unless Windows made one up (it then holds '&').
      const auto slash = instance.rfind('\\');
      if (instance.rfind("USB\\", 0) == 0 && slash != std::string::npos &&
          instance.find('&', slash) == std::string::npos)
        p.serial = instance.substr(slash + 1);
    }
    if (!p.port.empty()) out[p.port] = std::move(p);
  }
  ::SetupDiDestroyDeviceInfoList(set);
  return out;
}

// HKLM\HARDWARE\DEVICEMAP\SERIALCOMM: "\Device\Serial0" = "COM1", by port.
std::map<std::string, std::string> win_serialcomm() {
  std::map<std::string, std::string> out;
  HKEY key = nullptr;
  if (::RegOpenKeyExW(HKEY_LOCAL_MACHINE, L"HARDWARE\\DEVICEMAP\\SERIALCOMM", 0, KEY_READ, &key) !=
      ERROR_SUCCESS)
    return out;
  for (DWORD i = 0;; ++i) {
    std::vector<wchar_t> name(256), data(256);
    DWORD name_len = static_cast<DWORD>(name.size());
    DWORD type = 0, bytes = static_cast<DWORD>(data.size() * sizeof(wchar_t));
    const LONG rc = ::RegEnumValueW(key, i, name.data(), &name_len, nullptr, &type,
                                    reinterpret_cast<BYTE*>(data.data()), &bytes);
    if (rc == ERROR_NO_MORE_ITEMS) break;
    if (rc != ERROR_SUCCESS || type != REG_SZ) continue;
    out[win_utf8(win_reg_text(data, bytes))] = win_utf8(std::wstring(name.data(), name_len));
  }
  ::RegCloseKey(key);
  return out;
}

}  // namespace

std::string port_user(const std::string& device, const PortRoots&) {
  if (auto h = transport::port_holder(device))
    return (h->holder.empty() ? "a program" : h->holder) + " (PID " + std::to_string(h->pid) + ")";
  return "";
}

const char* where_ports_are_looked_for() {
  return "among the COM ports Windows knows; the Device Manager lists them under Ports (COM & "
         "LPT)";
}

std::vector<SerialPortInfo> list_ports(const PortRoots& roots) {
  auto known = win_setupapi_ports();
  const auto kernel = win_serialcomm();
  std::vector<SerialPortInfo> out;
  for (const auto& name : transport::list_serial_ports()) {
    SerialPortInfo p;
    if (auto it = known.find(name); it != known.end()) p = it->second;
    p.port = name;
    if (auto it = kernel.find(name); it != kernel.end()) p.device = it->second;
    p.held_by = port_user(name, roots);
    out.push_back(std::move(p));
  }
  return out;
}

}  // namespace lmcfg::ui
