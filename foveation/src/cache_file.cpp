#include "cache_file.hpp"

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <new>

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

std::string write_file_atomically(const std::filesystem::path& file, std::span<const ByteSpan> pieces) {
  std::error_code ec;
  if (file.has_parent_path()) std::filesystem::create_directories(file.parent_path(), ec);
  if (ec) return "cannot create cache directory " + file.parent_path().string() + ": " + ec.message();
  const std::filesystem::path tmp = file.string() + ".tmp";
  const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) return "cannot write cache file " + tmp.string() + ": " + std::strerror(errno);
  auto write_all = [fd](const void* data, std::size_t size) {
    const char* p = static_cast<const char*>(data);
    while (size > 0) {
      const ssize_t n = ::write(fd, p, std::min<std::size_t>(size, std::size_t{1} << 20));
      if (n < 0 && errno == EINTR) continue;
      if (n <= 0) return false;
      p += n;
      size -= std::size_t(n);
    }
    return true;
  };
  bool ok = true;
  for (const ByteSpan& b : pieces) ok = ok && write_all(b.data, b.size);
  const int saved_errno = errno;
  if (::close(fd) != 0) ok = false;
  if (!ok) {
    std::filesystem::remove(tmp, ec);
    return "write failed for cache file " + tmp.string() + ": " + std::strerror(saved_errno);
  }
  std::filesystem::rename(tmp, file, ec);
  if (ec) return "cannot move cache file into place " + file.string() + ": " + ec.message();
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
