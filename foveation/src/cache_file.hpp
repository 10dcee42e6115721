// FoveaRT's cache files (point set, neighbour table, interpolation table):
// written as pieces of bytes in order, checksummed, replaced atomically; read
// through a read-only mapping of the whole file.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <span>
#include <string>

namespace foveart::foveation::detail {

// A run of bytes of a file, written from its owner's memory (no copy).
struct ByteSpan {
  const void* data;
  std::size_t size;
};

template <class T>
ByteSpan bytes_of(const T* data, std::size_t count) {
  return {data, sizeof(T) * count};
}

// XXH3-64 of the pieces, as if concatenated.
std::uint64_t xxh3_of(std::span<const ByteSpan> pieces);

// Writes the pieces to `file`: into a new temp file `.<name>.<random>.tmp` in
// the same directory (O_CREAT | O_EXCL | O_NOFOLLOW: never an existing file or
// a planted symlink), fsync, then rename over `file`. Readers and concurrent
// writers never see a partial file under the final name; a symlink at the
// final name is replaced, never followed. Creates the directory; writes in
// 1 MB pieces (one 442 MB write measured 5-10x slower here). Returns an error
// naming the file, empty on success; every failure removes the temp file.
std::string write_file_atomically(const std::filesystem::path& file, std::span<const ByteSpan> pieces);

// A read-only private mapping of a whole file (bytes == nullptr when it is
// empty); unmapped with its last owner, so views into it can share `owner`.
struct MappedFile {
  std::shared_ptr<const void> owner;
  const std::uint8_t* bytes = nullptr;
  std::size_t size = 0;
};

// Maps `file`; nullopt with *why ("not found: the file is missing", cannot
// open / map, not a regular file) when it cannot.
std::optional<MappedFile> map_file(const std::filesystem::path& file, std::string* why);

}  // namespace foveart::foveation::detail
