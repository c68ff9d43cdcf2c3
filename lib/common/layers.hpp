#pragma once
// Firmware layers and their UPID ranges (LinRS §10.2), the one definition
// every part of lmcfg uses: 1 OS 0000h-0EFFh, 2 MC 1000h-1EFFh,
// 3 Intf 2000h-2EFFh, 4 Appl 3000h-3EFFh.
#include <cstdint>
#include <optional>
#include <string_view>

namespace lmcfg::layers {

inline constexpr int kCount = 4;
inline constexpr int kOS = 1, kMC = 2, kIntf = 3, kAppl = 4;

// 1..4, or 0 when the UPID lies in no layer's range.
int of_upid(std::uint32_t upid) noexcept;
// 0000h, 1000h, 2000h, 3000h; FFFFh when `layer` is not 1..4.
std::uint16_t base_upid(int layer) noexcept;
// "OS", "MC", "Intf", "Appl"; "?" when `layer` is not 1..4.
std::string_view name(int layer) noexcept;
// Case-insensitive "os", "mc", "intf", "appl" -> 1..4.
std::optional<int> from_name(std::string_view name) noexcept;

}  // namespace lmcfg::layers
