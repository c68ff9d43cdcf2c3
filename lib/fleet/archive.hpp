#pragma once
// The fleet archive: an ordinary git repository (libgit2) holding one
// configuration file per drive position, <name>.json. Each fleet run is one
// commit; history, review and replication are git's (docs/fleet.md).
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "common/result.hpp"

struct git_repository;

namespace lmcfg::fleet {

struct CommitInfo {
  std::string id;       // full hex object id
  std::string summary;  // first line of the message
  std::string message;  // the whole message
};

// One entry of a file's history (git log -- FILE).
struct HistoryEntry {
  CommitInfo commit;
  std::int64_t time = 0;  // committer time, seconds since the epoch (UTC)
  std::string author;     // "Name <email>"
};

// An annotated tag object a ref under refs/lmcfg/ points to (a position's
// approved configuration, fleet/approved.hpp): the commit it names, who made
// it (the tagger's name), when, and its message.
struct TagRecord {
  std::string commit;     // full hex id of the commit the tag points to
  std::int64_t time = 0;  // the tagger's time, seconds since the epoch (UTC)
  std::string tagger;     // the tagger's name
  std::string message;
};

// The trailers of a commit message ("Operator: ana"), in order, as git
// interpret-trailers reads them (libgit2's git_message_trailers): the last
// paragraph, when every line of it is "Key: value".
std::vector<std::pair<std::string, std::string>> message_trailers(const std::string& message);

class Archive {
 public:
  // Opens the repository at `dir` (its work tree's top, not a subfolder).
  // create: a directory that does not exist or is empty becomes a new
  // repository. A directory with files that is not a repository is refused
  // (Errc::invalid_argument), as is a bare repository.
  static Result<Archive> open(const std::string& dir, bool create);

  Archive(Archive&&) noexcept;
  Archive& operator=(Archive&&) noexcept;
  ~Archive();

  const std::string& dir() const { return dir_; }
  // The commit `rev` names ("HEAD", a hash, "HEAD~2", a tag). nullopt: HEAD of
  // a repository with no commit yet. Errc::not_found for a name git does not know.
  Result<std::optional<CommitInfo>> resolve(const std::string& rev) const;
  // The content of `path` (relative to the top) in revision `rev`; nullopt
  // when that revision has no such file (or there is no commit yet).
  Result<std::optional<std::string>> read(const std::string& path,
                                          const std::string& rev = "HEAD") const;
  // The commits reachable from HEAD that changed `path` (added, modified or
  // removed it), newest first, at most `limit`. Empty without commits.
  // `also`: commits that did not change it but are taken all the same (fleet
  // restore's empty recording commits, by their message).
  Result<std::vector<HistoryEntry>> history(
      const std::string& path, std::size_t limit = 100,
      const std::function<bool(const CommitInfo&)>& also = {}) const;
  // Where to write `path` (relative to the top, '/'-separated) in the work
  // tree. Errc::file_error when the file or a folder on its way is a symbolic
  // link, or is ".git": the archive never writes through a link (out of
  // itself) or into git's own folder. Folders that do not exist yet are fine.
  Result<std::string> work_path(const std::string& path) const;
  // Stages `paths` (files the caller wrote in the work tree) and commits them
  // with `message`. nullopt, and no commit, when the tree equals HEAD's,
  // unless allow_empty (a record such as "restored press3/z-axis").
  // The author and committer: set_author's when set; otherwise git's
  // configuration (user.name, user.email), else "lmcfg fleet".
  Result<std::optional<CommitInfo>> commit(const std::vector<std::string>& paths,
                                           const std::string& message, bool allow_empty = false);
  // Who this archive's commits are by from now on ("lmcfg serve on HOST"): a
  // program that commits for others, the person in the message's trailers.
  void set_author(std::string name, std::string email) {
    author_name_ = std::move(name);
    author_email_ = std::move(email);
  }
  // Points `ref` ("refs/lmcfg/approved/press3/z") at a new annotated tag
  // object naming commit `commit_id` (full hex), made by `who` at `time`
  // (seconds since the epoch) with `message`; an earlier value of the ref is
  // replaced (the tag objects stay in the repository). Errc::invalid_argument
  // for a name git does not allow as a ref, Errc::not_found for an unknown commit.
  Result<void> set_tag_ref(const std::string& ref, const std::string& commit_id,
                           const std::string& who, std::int64_t time, const std::string& message);
  // What `ref` points to; nullopt when there is no such ref. A ref that does
  // not point to an annotated tag is Errc::file_error (someone else wrote it).
  Result<std::optional<TagRecord>> tag_ref(const std::string& ref) const;
  // Removes the lock files git and libgit2 leave when a process is killed
  // between creating a lock and renaming it into place (index.lock, HEAD.lock,
  // config.lock, packed-refs.lock, refs/**/*.lock): while one is there every
  // commit fails. Only for a repository no other process is writing (lmcfg
  // serve at start, on its own archive). The files removed, relative to the
  // git directory.
  Result<std::vector<std::string>> remove_stale_locks();
  // Pushes the current branch to `remote` (a configured remote's name or a
  // URL/path), same branch name there.
  Result<void> push(const std::string& remote);

 private:
  Archive(std::string dir, git_repository* repo) : dir_(std::move(dir)), repo_(repo) {}
  std::string dir_;
  std::string author_name_, author_email_;  // set_author; "" = git's configuration
  git_repository* repo_ = nullptr;
};

}  // namespace lmcfg::fleet
