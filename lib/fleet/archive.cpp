#include "fleet/archive.hpp"

#include <git2.h>

#include <filesystem>
#include <mutex>

#include "common/bytes.hpp"
#include "common/text.hpp"

namespace lmcfg::fleet {
namespace {

void init_libgit2() {
  static std::once_flag once;
  std::call_once(once, [] { git_libgit2_init(); });
}

Error git_failure(Errc code, const std::string& what) {
  const ::git_error* e = git_error_last();
  return Error(code, what + ": " + (e && e->message ? e->message : "libgit2 error"));
}

template <typename T, void (*Free)(T*)>
struct Owned {
  T* p = nullptr;
  Owned() = default;
  Owned(const Owned&) = delete;
  Owned& operator=(const Owned&) = delete;
  ~Owned() {
    if (p) Free(p);
  }
};
using Object = Owned<git_object, git_object_free>;
using Commit = Owned<git_commit, git_commit_free>;
using Tree = Owned<git_tree, git_tree_free>;
using Index = Owned<git_index, git_index_free>;
using Signature = Owned<git_signature, git_signature_free>;
using Reference = Owned<git_reference, git_reference_free>;
using Remote = Owned<git_remote, git_remote_free>;
using Walk = Owned<git_revwalk, git_revwalk_free>;
using Entry = Owned<git_tree_entry, git_tree_entry_free>;
using Tag = Owned<git_tag, git_tag_free>;

// The blob id of `path` in `c`'s tree; nullopt when the tree has no such file.
std::optional<git_oid> blob_at(const git_commit* c, const std::string& path) {
  Tree tree;
  if (git_commit_tree(&tree.p, c) != 0) return std::nullopt;
  Entry e;
  if (git_tree_entry_bypath(&e.p, tree.p, path.c_str()) != 0) return std::nullopt;
  return *git_tree_entry_id(e.p);
}

std::string oid_hex(const git_oid& oid) {
  char buf[GIT_OID_HEXSZ + 1];
  git_oid_tostr(buf, sizeof buf, &oid);
  return buf;
}

CommitInfo info_of(const git_commit* c) {
  const char* summary = git_commit_summary(const_cast<git_commit*>(c));
  const char* message = git_commit_message(c);
  // A message made by hand (git commit) may hold any bytes: shown with the
  // bytes that are not UTF-8 escaped ("\\xFF"), so every page, JSON answer and
  // `fleet log --json` can carry it.
  return CommitInfo{oid_hex(*git_commit_id(c)), escape_invalid_utf8(summary ? summary : ""),
                    escape_invalid_utf8(message ? message : "")};
}

bool unborn(git_repository* repo) { return git_repository_head_unborn(repo) == 1; }

}  // namespace

Result<Archive> Archive::open(const std::string& dir, bool create) {
  init_libgit2();
  namespace fs = std::filesystem;
  std::error_code ec;
  const bool exists = fs::exists(dir, ec);
  if (exists && !fs::is_directory(dir, ec))
    return Error(Errc::invalid_argument, "archive " + dir + " is not a directory");
  git_repository* repo = nullptr;
  if (exists &&
      git_repository_open_ext(&repo, dir.c_str(), GIT_REPOSITORY_OPEN_NO_SEARCH, nullptr) == 0) {
    if (git_repository_is_bare(repo)) {
      git_repository_free(repo);
      return Error(Errc::invalid_argument,
                   "archive " + dir +
                       " is a bare git repository; give a clone with a work tree (push to the "
                       "bare one with --push)");
    }
    return Archive(dir, repo);
  }
  const bool empty = !exists || fs::is_empty(dir, ec);
  if (!create || !empty) {
    return Error(Errc::invalid_argument,
                 "archive " + dir + " is not a git repository" +
                     (create ? " (and not empty, so it is not made one: give an empty or new "
                               "directory, or run git init there)"
                             : ""));
  }
  fs::create_directories(dir, ec);
  if (ec) return Error(Errc::file_error, "archive " + dir + ": " + ec.message());
  if (git_repository_init(&repo, dir.c_str(), 0) != 0)
    return git_failure(Errc::file_error, "archive " + dir + ": git init");
  return Archive(dir, repo);
}

Archive::Archive(Archive&& o) noexcept
    : dir_(std::move(o.dir_)),
      author_name_(std::move(o.author_name_)),
      author_email_(std::move(o.author_email_)),
      repo_(o.repo_) {
  o.repo_ = nullptr;
}
Archive& Archive::operator=(Archive&& o) noexcept {
  if (this != &o) {
    if (repo_) git_repository_free(repo_);
    dir_ = std::move(o.dir_);
    author_name_ = std::move(o.author_name_);
    author_email_ = std::move(o.author_email_);
    repo_ = o.repo_;
    o.repo_ = nullptr;
  }
  return *this;
}
Archive::~Archive() {
  if (repo_) git_repository_free(repo_);
}

Result<std::optional<CommitInfo>> Archive::resolve(const std::string& rev) const {
  if (rev == "HEAD" && unborn(repo_)) return std::optional<CommitInfo>();
  Object obj;
  if (git_revparse_single(&obj.p, repo_, (rev + "^{commit}").c_str()) != 0)
    return git_failure(Errc::not_found, "archive " + dir_ + ": revision '" + rev + "'");
  return std::optional<CommitInfo>(info_of(reinterpret_cast<git_commit*>(obj.p)));
}

Result<std::optional<std::string>> Archive::read(const std::string& path,
                                                 const std::string& rev) const {
  // The commit's tree only: resolve() would copy and check its whole message
  // (a first backup's lists every position), once per file read.
  if (rev == "HEAD" && unborn(repo_)) return std::optional<std::string>();
  Object obj;
  if (git_revparse_single(&obj.p, repo_, (rev + "^{commit}").c_str()) != 0)
    return git_failure(Errc::not_found, "archive " + dir_ + ": revision '" + rev + "'");
  const std::string where = "archive " + dir_ + ": " + path + " at " + rev;
  Tree tree;
  if (git_commit_tree(&tree.p, reinterpret_cast<git_commit*>(obj.p)) != 0)
    return git_failure(Errc::file_error, where);
  Entry e;
  const int rc = git_tree_entry_bypath(&e.p, tree.p, path.c_str());
  if (rc == GIT_ENOTFOUND) return std::optional<std::string>();
  if (rc != 0) return git_failure(Errc::file_error, where);
  if (git_tree_entry_type(e.p) != GIT_OBJECT_BLOB)
    return Error(Errc::file_error, where + " is not a file");
  Object blob;
  if (git_tree_entry_to_object(&blob.p, repo_, e.p) != 0)
    return git_failure(Errc::file_error, where);
  auto* b = reinterpret_cast<git_blob*>(blob.p);
  return std::optional<std::string>(
      std::string(static_cast<const char*>(git_blob_rawcontent(b)), git_blob_rawsize(b)));
}

Result<std::optional<CommitInfo>> Archive::commit(const std::vector<std::string>& paths,
                                                  const std::string& message, bool allow_empty) {
  const std::string where = "archive " + dir_;
  Index index;
  if (git_repository_index(&index.p, repo_) != 0) return git_failure(Errc::file_error, where);
  for (const auto& p : paths) {
    if (git_index_add_bypath(index.p, p.c_str()) != 0)
      return git_failure(Errc::file_error, where + ": staging " + p);
  }
  if (git_index_write(index.p) != 0) return git_failure(Errc::file_error, where + ": index");
  git_oid tree_id;
  if (git_index_write_tree(&tree_id, index.p) != 0)
    return git_failure(Errc::file_error, where + ": tree");
  Commit parent;
  if (!unborn(repo_)) {
    git_oid head;
    if (git_reference_name_to_id(&head, repo_, "HEAD") != 0 ||
        git_commit_lookup(&parent.p, repo_, &head) != 0)
      return git_failure(Errc::file_error, where + ": HEAD");
    if (!allow_empty && git_oid_equal(git_commit_tree_id(parent.p), &tree_id))
      return std::optional<CommitInfo>();
  } else if (!allow_empty && paths.empty()) {
    return std::optional<CommitInfo>();
  }
  Tree tree;
  if (git_tree_lookup(&tree.p, repo_, &tree_id) != 0) return git_failure(Errc::file_error, where);
  Signature sig;
  // Without user.name/user.email in git's configuration the archive still
  // records who wrote it: the tool.
  if (!author_name_.empty()) {
    if (git_signature_now(&sig.p, author_name_.c_str(), author_email_.c_str()) != 0)
      return git_failure(Errc::file_error, where + ": signature");
  } else if (git_signature_default(&sig.p, repo_) != 0 &&
             git_signature_now(&sig.p, "lmcfg fleet", "lmcfg@localhost") != 0) {
    return git_failure(Errc::file_error, where + ": signature");
  }
  const git_commit* parents[1] = {parent.p};
  git_oid id;
  if (git_commit_create(&id, repo_, "HEAD", sig.p, sig.p, nullptr, message.c_str(), tree.p,
                        parent.p ? 1 : 0, parents) != 0)
    return git_failure(Errc::file_error, where + ": commit");
  Commit made;
  if (git_commit_lookup(&made.p, repo_, &id) != 0) return git_failure(Errc::file_error, where);
  return std::optional<CommitInfo>(info_of(made.p));
}

std::vector<std::pair<std::string, std::string>> message_trailers(const std::string& message) {
  std::vector<std::pair<std::string, std::string>> out;
  init_libgit2();  // callable before any Archive exists
  git_message_trailer_array arr{};
  if (git_message_trailers(&arr, message.c_str()) != 0) return out;
  for (std::size_t i = 0; i < arr.count; ++i)
    out.emplace_back(arr.trailers[i].key ? arr.trailers[i].key : "",
                     arr.trailers[i].value ? arr.trailers[i].value : "");
  git_message_trailer_array_free(&arr);
  return out;
}

Result<std::vector<HistoryEntry>> Archive::history(
    const std::string& path, std::size_t limit,
    const std::function<bool(const CommitInfo&)>& also) const {
  std::vector<HistoryEntry> out;
  if (unborn(repo_)) return out;
  const std::string where = "archive " + dir_ + ": history of " + path;
  Walk walk;
  if (git_revwalk_new(&walk.p, repo_) != 0 || git_revwalk_push_head(walk.p) != 0)
    return git_failure(Errc::file_error, where);
  // Newest first as git log --date-order: commit times have one-second
  // resolution, and a time sort alone leaves the commits of one second (a
  // backup and the restore record after it) in any order; topological order
  // puts each child before its parent.
  git_revwalk_sorting(walk.p, GIT_SORT_TOPOLOGICAL | GIT_SORT_TIME);
  git_oid id;
  while (out.size() < limit && git_revwalk_next(&id, walk.p) == 0) {
    Commit c;
    if (git_commit_lookup(&c.p, repo_, &id) != 0) return git_failure(Errc::file_error, where);
    const auto mine = blob_at(c.p, path);
    bool changed = true;
    if (git_commit_parentcount(c.p) > 0) {
      Commit parent;
      if (git_commit_parent(&parent.p, c.p, 0) != 0) return git_failure(Errc::file_error, where);
      const auto theirs = blob_at(parent.p, path);
      changed =
          mine.has_value() != theirs.has_value() || (mine && git_oid_cmp(&*mine, &*theirs) != 0);
    } else {
      changed = mine.has_value();
    }
    auto info = info_of(c.p);
    if (!changed && !(also && also(info))) continue;
    const git_signature* a = git_commit_author(c.p);
    out.push_back(HistoryEntry{std::move(info), static_cast<std::int64_t>(git_commit_time(c.p)),
                               escape_invalid_utf8(std::string(a->name ? a->name : "") + " <" +
                                                   (a->email ? a->email : "") + ">")});
  }
  return out;
}

Result<std::string> Archive::work_path(const std::string& path) const {
  namespace fs = std::filesystem;
  fs::path at = dir_;
  const fs::path rel(path);
  bool exists = true;  // so far; below a missing folder nothing can be a link
  for (const auto& part : rel) {
    at /= part;
    if (part == "." || part == ".." || iequals(part.string(), ".git") || part.empty()) {
      return Error(Errc::file_error, "archive " + dir_ + ": will not write " + path + " (its '" +
                                         part.string() +
                                         "' leaves the work tree or enters git's folder)");
    }
    if (!exists) continue;
    std::error_code ec;
    const auto st = fs::symlink_status(at, ec);
    exists = !ec && st.type() != fs::file_type::not_found;
    if (exists && st.type() == fs::file_type::symlink) {
      const auto target = fs::read_symlink(at, ec);
      return Error(Errc::file_error,
                   "archive " + dir_ + ": " + at.lexically_relative(dir_).string() +
                       " is a symbolic link (to " + target.string() +
                       "); the archive writes no file through a link: replace it with a folder "
                       "or remove it");
    }
  }
  return (fs::path(dir_) / rel).string();
}

Result<void> Archive::set_tag_ref(const std::string& ref, const std::string& commit_id,
                                  const std::string& who, std::int64_t time,
                                  const std::string& message) {
  const std::string where = "archive " + dir_ + ": " + ref;
  int valid = 0;
  if (git_reference_name_is_valid(&valid, ref.c_str()) != 0 || !valid)
    return Error(Errc::invalid_argument, where + " is not a name git allows for a reference");
  git_oid id;
  Object target;
  if (git_oid_fromstr(&id, commit_id.c_str()) != 0 ||
      git_object_lookup(&target.p, repo_, &id, GIT_OBJECT_COMMIT) != 0)
    return git_failure(Errc::not_found, where + ": commit " + commit_id);
  Signature sig;
  if (git_signature_new(&sig.p, who.empty() ? "lmcfg" : who.c_str(), "lmcfg@localhost",
                        static_cast<git_time_t>(time), 0) != 0)
    return git_failure(Errc::invalid_argument, where + ": tagger '" + who + "'");
  // The tag's own name is the ref's tail: `git cat-file tag` shows it.
  const std::string name = ref.rfind("refs/", 0) == 0 ? ref.substr(5) : ref;
  git_oid tag_id;
  if (git_tag_annotation_create(&tag_id, repo_, name.c_str(), target.p, sig.p, message.c_str()) !=
      0)
    return git_failure(Errc::file_error, where + ": tag");
  Reference made;
  if (git_reference_create(&made.p, repo_, ref.c_str(), &tag_id, 1, message.c_str()) != 0)
    return git_failure(Errc::file_error, where);
  return {};
}

Result<std::optional<TagRecord>> Archive::tag_ref(const std::string& ref) const {
  const std::string where = "archive " + dir_ + ": " + ref;
  Reference r;
  const int rc = git_reference_lookup(&r.p, repo_, ref.c_str());
  if (rc == GIT_ENOTFOUND || rc == GIT_EINVALIDSPEC) return std::optional<TagRecord>();
  if (rc != 0) return git_failure(Errc::file_error, where);
  const git_oid* id = git_reference_target(r.p);
  Tag tag;
  if (!id || git_tag_lookup(&tag.p, repo_, id) != 0)
    return Error(Errc::file_error,
                 where +
                     " does not point to an annotated tag (written by something other than "
                     "lmcfg?): remove it with git update-ref -d " +
                     ref);
  TagRecord out;
  out.commit = oid_hex(*git_tag_target_id(tag.p));
  if (const git_signature* t = git_tag_tagger(tag.p)) {
    out.time = static_cast<std::int64_t>(t->when.time);
    out.tagger = t->name ? t->name : "";
  }
  const char* m = git_tag_message(tag.p);
  out.message = m ? m : "";
  return std::optional<TagRecord>(std::move(out));
}

Result<std::vector<std::string>> Archive::remove_stale_locks() {
  namespace fs = std::filesystem;
  const fs::path git_dir = git_repository_path(repo_);
  std::vector<std::string> removed;
  std::error_code ec;
  auto remove = [&](const fs::path& p) -> Result<void> {
    if (!fs::is_regular_file(p, ec)) return {};
    if (!fs::remove(p, ec) && ec)
      return Error(Errc::file_error, "archive " + dir_ + ": cannot remove the stale lock " +
                                         p.string() + ": " + ec.message());
    removed.push_back(p.lexically_relative(git_dir).string());
    return {};
  };
  for (const char* name : {"index.lock", "HEAD.lock", "config.lock", "packed-refs.lock"})
    LMCFG_TRY(remove(git_dir / name));
  if (fs::is_directory(git_dir / "refs", ec)) {
    std::vector<fs::path> locks;
    for (auto it = fs::recursive_directory_iterator(git_dir / "refs", ec);
         !ec && it != fs::recursive_directory_iterator(); it.increment(ec))
      if (it->path().extension() == ".lock") locks.push_back(it->path());
    for (const auto& l : locks) LMCFG_TRY(remove(l));
  }
  return removed;
}

Result<void> Archive::push(const std::string& remote_name) {
  const std::string where = "archive " + dir_ + ": push to " + remote_name;
  Reference head;
  if (git_repository_head(&head.p, repo_) != 0) return git_failure(Errc::file_error, where);
  const std::string branch = git_reference_name(head.p);  // refs/heads/main
  // A configured remote's URL (remote.NAME.url), else the argument itself as a
  // URL or path. Not through git_remote_lookup: with url.*.insteadOf rewriting
  // libgit2 1.5 leaks a PCRE match block per remote (LeakSanitizer), so the
  // rewriting is skipped and URLs are used as configured.
  std::string url = remote_name;
  git_config* config = nullptr;
  if (git_repository_config_snapshot(&config, repo_) == 0) {
    const char* configured = nullptr;
    if (git_config_get_string(&configured, config, ("remote." + remote_name + ".url").c_str()) ==
            0 &&
        configured)
      url = configured;
    git_config_free(config);
  }
  Remote remote;
  git_remote_create_options create;
  git_remote_create_options_init(&create, GIT_REMOTE_CREATE_OPTIONS_VERSION);
  create.repository = repo_;
  create.flags = GIT_REMOTE_CREATE_SKIP_INSTEADOF | GIT_REMOTE_CREATE_SKIP_DEFAULT_FETCHSPEC;
  if (git_remote_create_with_opts(&remote.p, url.c_str(), &create) != 0)
    return git_failure(Errc::invalid_argument, where);
  std::string spec = branch + ":" + branch;
  char* specs[] = {spec.data()};
  const git_strarray refspecs = {specs, 1};
  git_push_options opts;
  git_push_options_init(&opts, GIT_PUSH_OPTIONS_VERSION);
  if (git_remote_push(remote.p, &refspecs, &opts) != 0) return git_failure(Errc::io_error, where);
  return {};
}

}  // namespace lmcfg::fleet
