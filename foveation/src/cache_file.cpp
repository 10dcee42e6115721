#include "cache_file.hpp"

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <cstdio>
#include <new>
#include <random>

#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include <xxhash.h>

namespace foveart::foveation::detail {

std::uint64_t xxh3_of(std::span<const ByteSpan> pieces) {
  XXH3_state_t* state = XXH3_createState();
  if (state == nullptr) throw std::bad_alloc();
  XXH3_64bits_reset(state);
  for (const ByteSpan& b : pieces) XXH3_64bits_update(state, b.data, b.size);
  const std::uint64_t digest = XXH3_64bits_digest(state);
  XXH3_freeState(state);
  return digest;
}

namespace {

std::string errno_text(int error) { return std::strerror(error); }

// A file descriptor closed with its owner.
struct Fd {
  int fd = -1;
  explicit Fd(int f) : fd(f) {}
  Fd(const Fd&) = delete;
  Fd& operator=(const Fd&) = delete;
  ~Fd() {
    if (fd >= 0) ::close(fd);
  }
};

bool write_all(int fd, const void* data, std::size_t size) {
  const char* p = static_cast<const char*>(data);
  while (size > 0) {
    const ssize_t n = ::write(fd, p, std::min<std::size_t>(size, std::size_t{1} << 20));
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) return false;
    if (n == 0) {
      errno = EIO;
      return false;
    }
    p += n;
    size -= std::size_t(n);
  }
  return true;
}

// A new file `.<name>.<random>.tmp` in the directory `dir_fd`, created
// exclusively (never an existing file or a symlink planted there).
int create_temp(int dir_fd, const std::string& name, std::string* out_temp_name) {
  std::random_device entropy;
  for (int attempt = 0; attempt < 64; ++attempt) {
    const std::uint64_t r = (std::uint64_t(entropy()) << 32) ^ entropy() ^ std::uint64_t(::getpid());
    char suffix[17];
    std::snprintf(suffix, sizeof suffix, "%016llx", static_cast<unsigned long long>(r));
    *out_temp_name = "." + name + "." + suffix + ".tmp";
    const int fd = ::openat(dir_fd, out_temp_name->c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0644);
    if (fd >= 0 || errno != EEXIST) return fd;
  }
  errno = EEXIST;
  return -1;
}

}  // namespace

std::string write_file_atomically(const std::filesystem::path& file, std::span<const ByteSpan> pieces) {
  const std::filesystem::path dir = file.has_parent_path() ? file.parent_path() : std::filesystem::path(".");
  const std::string name = file.filename().string();
  if (name.empty() || name == "." || name == "..") return "cannot write cache file " + file.string() + ": no file name";
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) return "cannot create cache directory " + dir.string() + ": " + ec.message();
  // Temp file and rename both relative to one open directory: the pair cannot be split across two directories.
  const Fd dir_fd(::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC));
  if (dir_fd.fd < 0) return "cannot open cache directory " + dir.string() + ": " + errno_text(errno);
  std::string temp_name;
  Fd fd(create_temp(dir_fd.fd, name, &temp_name));
  if (fd.fd < 0) return "cannot create a temp file in cache directory " + dir.string() + ": " + errno_text(errno);
  const std::string temp_path = (dir / temp_name).string();
  // Every failure removes the temp file and names both files.
  auto fail = [&](const std::string& what, int error) {
    ::unlinkat(dir_fd.fd, temp_name.c_str(), 0);
    return what + " cache file " + file.string() + " (temp " + temp_path + "): " + errno_text(error);
  };
  for (const ByteSpan& b : pieces) {
    if (!write_all(fd.fd, b.data, b.size)) return fail("write failed for", errno);
  }
  // Durable before visible: a crash after the rename never leaves a short file under the final name.
  if (::fsync(fd.fd) != 0) return fail("fsync failed for", errno);
  const int closed = ::close(fd.fd);
  fd.fd = -1;
  if (closed != 0) return fail("close failed for", errno);
  // rename replaces the final name itself, a symlink there included: nothing it pointed to is written.
  if (::renameat(dir_fd.fd, temp_name.c_str(), dir_fd.fd, name.c_str()) != 0) {
    return fail("cannot move into place the", errno);
  }
  ::fsync(dir_fd.fd);  // the rename itself; a failure here loses only the cache entry
  return {};
}

std::optional<MappedFile> map_file(const std::filesystem::path& file, std::string* why) {
  const int fd = ::open(file.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) {
    *why = (errno == ENOENT) ? "not found: the file is missing" : std::string("cannot open: ") + std::strerror(errno);
    return std::nullopt;
  }
  struct stat st {};
  if (::fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) {
    ::close(fd);
    *why = "not a regular file";
    return std::nullopt;
  }
  MappedFile m;
  m.size = std::size_t(st.st_size);
  if (m.size == 0) {
    ::close(fd);
    return m;  // nothing to map; the header check rejects it
  }
  // MAP_POPULATE: fault the (page-cached) file in at once instead of per page.
  void* p = ::mmap(nullptr, m.size, PROT_READ, MAP_PRIVATE | MAP_POPULATE, fd, 0);
  ::close(fd);
  if (p == MAP_FAILED) {
    *why = std::string("cannot map: ") + std::strerror(errno);
    return std::nullopt;
  }
  const std::size_t size = m.size;
  m.owner = std::shared_ptr<const void>(p, [size](const void* q) { ::munmap(const_cast<void*>(q), size); });
  m.bytes = static_cast<const std::uint8_t*>(p);
  return m;
}

}  // namespace foveart::foveation::detail
