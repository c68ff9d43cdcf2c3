#include "common/layers.hpp"

#include <array>

#include "common/bytes.hpp"

namespace lmcfg::layers {

namespace {
constexpr std::array<std::string_view, kCount> kNames{"OS", "MC", "Intf", "Appl"};
}

int of_upid(std::uint32_t upid) noexcept {
  if (upid > 0x3EFF || (upid & 0x0FFF) > 0x0EFF) return 0;
  return static_cast<int>(upid >> 12) + 1;
}

std::uint16_t base_upid(int layer) noexcept {
  if (layer < 1 || layer > kCount) return 0xFFFF;
  return static_cast<std::uint16_t>((layer - 1) << 12);
}

std::string_view name(int layer) noexcept {
  if (layer < 1 || layer > kCount) return "?";
  return kNames[static_cast<std::size_t>(layer - 1)];
}

std::optional<int> from_name(std::string_view text) noexcept {
  for (int l = 1; l <= kCount; ++l)
    if (iequals(kNames[static_cast<std::size_t>(l - 1)], text)) return l;
  return std::nullopt;
}

}  // namespace lmcfg::layers
