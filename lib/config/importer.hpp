#pragma once
// Extension point for importing configurations saved by other tools.
//
// No importer is implemented: the seeds document no LinMot-Talk (or other)
// configuration file format, so none is invented. An importer for a format
// that gets documented later implements Importer and is added to the
// registry (e.g. by the tool at start-up):
//
//   lmcfg::config::ImporterRegistry::instance().add(std::make_unique<MyImporter>());
//
// Importers produce a DriveConfig; the scope they set must say honestly what
// the foreign file captured. Results go through validate() like any file.
#include <filesystem>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "common/result.hpp"
#include "config/model.hpp"

namespace lmcfg::config {

class Importer {
 public:
  virtual ~Importer() = default;
  // Short, stable identifier used on command lines ("linmot-talk-xyz").
  virtual std::string_view name() const = 0;
  virtual std::string_view description() const = 0;
  // Whether this importer recognises the file (by extension and/or the first bytes).
  virtual bool can_import(const std::filesystem::path& path, std::string_view head) const = 0;
  // `source` names the input in messages.
  virtual Result<DriveConfig> import(std::string_view content, std::string_view source) const = 0;
};

class ImporterRegistry {
 public:
  static ImporterRegistry& instance();
  // Errc::invalid_argument when an importer of the same name exists.
  Result<void> add(std::unique_ptr<Importer> importer);
  const Importer* find(std::string_view name) const;
  // First importer whose can_import() accepts the file; nullptr when none.
  const Importer* detect(const std::filesystem::path& path, std::string_view head) const;
  std::vector<const Importer*> list() const;

 private:
  std::vector<std::unique_ptr<Importer>> importers_;
};

}  // namespace lmcfg::config
