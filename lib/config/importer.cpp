#include "config/importer.hpp"

namespace lmcfg::config {

ImporterRegistry& ImporterRegistry::instance() {
  static ImporterRegistry r;
  return r;
}

Result<void> ImporterRegistry::add(std::unique_ptr<Importer> importer) {
  if (!importer) return Error(Errc::invalid_argument, "null importer");
  if (find(importer->name()))
    return Error(Errc::invalid_argument, "an importer named \"" + std::string(importer->name()) + "\" exists");
  importers_.push_back(std::move(importer));
  return {};
}

const Importer* ImporterRegistry::find(std::string_view name) const {
  for (const auto& i : importers_)
    if (i->name() == name) return i.get();
  return nullptr;
}

const Importer* ImporterRegistry::detect(const std::filesystem::path& path, std::string_view head) const {
  for (const auto& i : importers_)
    if (i->can_import(path, head)) return i.get();
  return nullptr;
}

std::vector<const Importer*> ImporterRegistry::list() const {
  std::vector<const Importer*> v;
  for (const auto& i : importers_) v.push_back(i.get());
  return v;
}

}  // namespace lmcfg::config
