#pragma once
// Git repositories for the archive tests, through the real git program.
#include <catch2/catch.hpp>
#include <cstdlib>
#include <filesystem>
#include <string>

namespace lmcfg::test {

// The repository's own committer ("Test Op <op@example.com>"), so commits do
// not depend on the user's ~/.gitconfig.
inline void set_git_identity(const std::filesystem::path& repo) {
  const std::string git = "git -C '" + repo.string() + "' config ";
  REQUIRE(std::system(
              (git + "user.name 'Test Op' && " + git + "user.email op@example.com").c_str()) == 0);
}

}  // namespace lmcfg::test
