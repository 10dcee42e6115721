// Bounds-checked reads of glTF accessors: every count, offset and stride read from
// the file is checked before a byte is read, so a broken file is a BadInput naming the
// accessor, never a read outside a buffer or a silently wrapped size.
#pragma once

#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

namespace tinygltf {
class Model;
struct Accessor;
}  // namespace tinygltf

namespace foveart::engine::gltf {

// Thrown inside the glTF loader only; load_gltf turns it into LoadResult::error.
struct BadInput : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// Size arithmetic on counts, offsets and strides read from the file: a result that
// does not fit in size_t is a BadInput naming `where`.
size_t checked_mul(size_t a, size_t b, const std::string& where);
size_t checked_add(size_t a, size_t b, const std::string& where);

class AccessorReader {
 public:
  explicit AccessorReader(const tinygltf::Model& model);

  // Component values of accessor `index` as floats (normalised integers mapped to [0,1]
  // or [-1,1]), *out_components per element, sparse substitution applied. `what` names
  // the accessor's use in every error.
  std::vector<float> floats(int index, const std::string& what, int* out_components) const;

  // An index accessor (unsigned integer scalars) as 32-bit indices.
  std::vector<uint32_t> indices(int index, const std::string& what) const;

 private:
  void check_zero_filled_count(const tinygltf::Accessor& a, const std::string& where) const;
  void view_range(const tinygltf::Accessor& a, int view_index, size_t offset, size_t count, size_t elem_bytes,
                  const std::string& what, const uint8_t** out_base, size_t* out_stride) const;
  void apply_sparse(const tinygltf::Accessor& a, int ncomp, int csize, const std::string& what,
                    std::vector<float>& out) const;

  const tinygltf::Model& model_;
  size_t buffer_bytes_ = 0;  // all buffers' bytes: the most elements a zero-filled accessor may claim
};

}  // namespace foveart::engine::gltf
