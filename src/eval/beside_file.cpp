// resolveBeside and liesWithin: a header's path confined to its file's folder (beside_file.h).
#include "eval/beside_file.h"

#include <algorithm>
#include <filesystem>
#include <system_error>

#include "io/atomic_file.h"
#include "io/file_hash.h"

namespace dentsim {
namespace {

namespace fs = std::filesystem;

// A path as it may be printed: control characters (a header could hold terminal escapes) become '?'.
std::string printable(const std::string& text) {
  std::string out = text.substr(0, 200);
  for (char& c : out)
    if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) c = '?';
  return out;
}

fs::path canonicalAsFarAsItExists(const fs::path& p) {
  std::error_code ec;
  fs::path absolute = fs::absolute(p, ec);
  if (ec) return p.lexically_normal();
  fs::path canonical = fs::weakly_canonical(absolute, ec);
  return ec ? absolute.lexically_normal() : canonical;
}

}  // namespace

bool liesWithin(const std::string& path, const std::string& folder) {
  const fs::path p = canonicalAsFarAsItExists(path);
  fs::path f = canonicalAsFarAsItExists(folder.empty() ? fs::path(".") : fs::path(folder));
  // Compared element by element, so that "/a/bc" does not pass for a file in "/a/b".
  auto pi = p.begin();
  for (auto fi = f.begin(); fi != f.end(); ++fi, ++pi) {
    if (fi->empty()) continue;  // a trailing separator
    if (pi == p.end() || *pi != *fi) return false;
  }
  return true;
}

Result<std::string> resolveBeside(const std::string& owner, const std::string& named, const std::string& what) {
  const fs::path folder = fs::path(owner).parent_path();
  const std::string why = " names \"" + printable(named) + "\"; a file names only files in its own folder or below it";
  if (named.empty()) return makeError(owner, what + " names no file");
  if (fs::path(named).is_absolute()) return makeError(owner, what + why + " (this is an absolute path)");
  const fs::path resolved = folder / named;
  if (!liesWithin(resolved.string(), folder.empty() ? "." : folder.string()))
    return makeError(owner, what + why + " (this one lies outside it)");
  return resolved.string();
}

Status copyFileAtomic(const std::string& from, const std::string& to) {
  if (sameFile(from, to)) return Ok{};
  const std::string temp = temporarySibling(to);
  std::error_code ec;
  fs::copy_file(from, temp, fs::copy_options::overwrite_existing, ec);
  if (ec) {
    discardTemporary(temp);
    return makeError(to, "cannot copy " + from + ": " + ec.message());
  }
  return commitTemporary(temp, to);
}

Result<std::string> nameBeside(const std::string& owner, const std::string& path, bool* copied) {
  *copied = false;
  std::error_code ec;
  const fs::path folder = fs::absolute(fs::path(owner), ec).parent_path();
  if (liesWithin(path, folder.string())) {
    const fs::path rel = fs::relative(canonicalAsFarAsItExists(path), canonicalAsFarAsItExists(folder), ec);
    if (!ec && !rel.empty()) return rel.generic_string();
  }
  if (!fs::is_regular_file(path, ec)) return makeError(path, "no such file to copy beside " + owner);
  const fs::path target = folder / fs::path(path).filename();
  if (fs::exists(target, ec) && !sameFile(path, target.string())) {
    auto a = fileHash(path), b = fileHash(target.string());
    if (!a || !b || *a != *b)
      return makeError(target.string(), "exists and differs from " + path + ", which the task would copy there: rename one");
  } else if (Status st = copyFileAtomic(path, target.string()); !st) {
    return st.error();
  } else {
    *copied = true;
  }
  return fs::path(path).filename().generic_string();
}

}  // namespace dentsim
