// Bounds-checked reads of glTF accessors (glTF 2.0, 3.6 "Binary data storage").
#include "gltf_accessors.hpp"

#define TINYGLTF_NO_STB_IMAGE_WRITE
#include <tiny_gltf.h>

#include <algorithm>
#include <cmath>
#include <cstring>

namespace foveart::engine::gltf {

size_t checked_mul(size_t a, size_t b, const std::string& where) {
  size_t r = 0;
  if (__builtin_mul_overflow(a, b, &r))
    throw BadInput(where + ": " + std::to_string(a) + " x " + std::to_string(b) + " overflows size_t");
  return r;
}

size_t checked_add(size_t a, size_t b, const std::string& where) {
  size_t r = 0;
  if (__builtin_add_overflow(a, b, &r))
    throw BadInput(where + ": " + std::to_string(a) + " + " + std::to_string(b) + " overflows size_t");
  return r;
}

namespace {

float component(const uint8_t* p, int type, bool normalized) {
  switch (type) {
    case TINYGLTF_COMPONENT_TYPE_FLOAT: { float f; std::memcpy(&f, p, 4); return f; }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: {
      const float v = static_cast<float>(*p);
      return normalized ? v / 255.0f : v;
    }
    case TINYGLTF_COMPONENT_TYPE_BYTE: {
      int8_t s; std::memcpy(&s, p, 1);
      return normalized ? std::max(static_cast<float>(s) / 127.0f, -1.0f) : static_cast<float>(s);
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
      uint16_t u; std::memcpy(&u, p, 2);
      return normalized ? static_cast<float>(u) / 65535.0f : static_cast<float>(u);
    }
    case TINYGLTF_COMPONENT_TYPE_SHORT: {
      int16_t s; std::memcpy(&s, p, 2);
      return normalized ? std::max(static_cast<float>(s) / 32767.0f, -1.0f)
                        : static_cast<float>(s);
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: {
      uint32_t u; std::memcpy(&u, p, 4); return static_cast<float>(u);
    }
    case TINYGLTF_COMPONENT_TYPE_INT: { int32_t s; std::memcpy(&s, p, 4); return static_cast<float>(s); }
    default: return 0.0f;
  }
}

uint32_t read_index(const uint8_t* p, int type) {
  switch (type) {
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return *p;
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: { uint16_t u; std::memcpy(&u, p, 2); return u; }
    default: { uint32_t u; std::memcpy(&u, p, 4); return u; }
  }
}

}  // namespace

AccessorReader::AccessorReader(const tinygltf::Model& model) : model_(model) {
  for (const tinygltf::Buffer& b : model_.buffers) buffer_bytes_ += b.data.size();
}

std::vector<float> AccessorReader::floats(int index, const std::string& what, int* out_components) const {
  if (index < 0 || static_cast<size_t>(index) >= model_.accessors.size())
    throw BadInput(what + ": accessor " + std::to_string(index) + " does not exist");
  const std::string where = what + ": accessor " + std::to_string(index);
  const tinygltf::Accessor& a = model_.accessors[index];
  const int ncomp = tinygltf::GetNumComponentsInType(static_cast<uint32_t>(a.type));
  const int csize = tinygltf::GetComponentSizeInBytes(static_cast<uint32_t>(a.componentType));
  if (ncomp <= 0 || csize <= 0 || ncomp > 16) throw BadInput(where + " has an invalid type");
  *out_components = ncomp;
  // The float count and its byte size must fit before anything is allocated or read.
  const size_t nvalues = checked_mul(a.count, static_cast<size_t>(ncomp), where + " count x components");
  checked_mul(nvalues, sizeof(float), where + " count x components x 4 bytes");
  check_zero_filled_count(a, where);
  const uint8_t* base = nullptr;
  size_t stride = 0;
  if (a.bufferView >= 0)
    view_range(a, a.bufferView, a.byteOffset, a.count, static_cast<size_t>(ncomp * csize), where, &base,
               &stride);
  std::vector<float> out(nvalues, 0.0f);
  if (base) {
    for (size_t i = 0; i < a.count; ++i)
      for (int c = 0; c < ncomp; ++c)
        out[i * ncomp + c] = component(base + i * stride + static_cast<size_t>(c * csize),
                                       a.componentType, a.normalized);
  }
  if (a.sparse.isSparse) apply_sparse(a, ncomp, csize, where, out);
  for (float v : out)
    if (!std::isfinite(v)) throw BadInput(where + " holds a non-finite value");
  return out;
}

// An accessor without a bufferView is zeros (plus its sparse values), so its count costs
// memory that no byte of the file backs. A real one (a morph target, a sparse attribute)
// has as many elements as a stored accessor beside it, each of at least one byte; a count
// beyond all the file's buffer bytes is a claim to refuse before allocating.
void AccessorReader::check_zero_filled_count(const tinygltf::Accessor& a, const std::string& where) const {
  if (a.bufferView >= 0 || a.count <= buffer_bytes_) return;
  throw BadInput(where + " has no bufferView and claims " + std::to_string(a.count) +
                 " elements, more than the file's " + std::to_string(buffer_bytes_) + " buffer bytes could describe");
}

// Checks, with overflow-checked arithmetic, that `count` elements of `elem_bytes` at
// `offset` + i x stride lie inside the buffer view and the view inside its buffer.
// `what` names the accessor in every error.
void AccessorReader::view_range(const tinygltf::Accessor& a, int view_index, size_t offset, size_t count,
                                size_t elem_bytes, const std::string& what, const uint8_t** out_base,
                                size_t* out_stride) const {
  if (view_index < 0 || static_cast<size_t>(view_index) >= model_.bufferViews.size())
    throw BadInput(what + ": bufferView " + std::to_string(view_index) + " does not exist");
  const tinygltf::BufferView& v = model_.bufferViews[view_index];
  if (v.buffer < 0 || static_cast<size_t>(v.buffer) >= model_.buffers.size())
    throw BadInput(what + ": buffer " + std::to_string(v.buffer) + " does not exist");
  const tinygltf::Buffer& b = model_.buffers[v.buffer];
  if (v.byteOffset > b.data.size() || v.byteLength > b.data.size() - v.byteOffset)
    throw BadInput(what + ": bufferView " + std::to_string(view_index) +
                   " lies outside its buffer (" + std::to_string(b.data.size()) + " bytes)");
  const int s = a.ByteStride(v);
  const size_t stride = s > 0 ? static_cast<size_t>(s) : elem_bytes;
  if (stride < elem_bytes && v.byteStride != 0)
    throw BadInput(what + ": byteStride smaller than an element");
  if (offset > v.byteLength)
    throw BadInput(what + ": byteOffset " + std::to_string(offset) + " lies past the end of bufferView " +
                   std::to_string(view_index) + " (" + std::to_string(v.byteLength) + " bytes)");
  if (count > 0) {
    const size_t last_at = checked_mul(count - 1, stride, what + " (count - 1) x byte stride");
    const size_t end = checked_add(checked_add(offset, last_at, what + " byteOffset + (count - 1) x byte stride"),
                                   elem_bytes, what + " byte range end");
    if (end > v.byteLength)
      throw BadInput(what + " reads past the end of bufferView " + std::to_string(view_index) + " (" +
                     std::to_string(end) + " > " + std::to_string(v.byteLength) + " bytes)");
  }
  *out_base = b.data.data() + v.byteOffset + offset;
  *out_stride = stride;
}

void AccessorReader::apply_sparse(const tinygltf::Accessor& a, int ncomp, int csize, const std::string& what,
                                  std::vector<float>& out) const {
  if (a.sparse.count < 0 || static_cast<size_t>(a.sparse.count) > a.count)
    throw BadInput(what + ": sparse count out of range");
  const size_t n = static_cast<size_t>(a.sparse.count);
  const int itype = a.sparse.indices.componentType;
  const int isize = tinygltf::GetComponentSizeInBytes(static_cast<uint32_t>(itype));
  if (isize <= 0) throw BadInput(what + ": sparse indices have an invalid component type");
  tinygltf::Accessor tmp;  // strides of sparse arrays are always tight
  const uint8_t* ibase = nullptr;
  const uint8_t* vbase = nullptr;
  size_t istride = 0;
  size_t vstride = 0;
  tmp.componentType = itype;
  tmp.type = TINYGLTF_TYPE_SCALAR;
  view_range(tmp, a.sparse.indices.bufferView, static_cast<size_t>(a.sparse.indices.byteOffset), n,
             static_cast<size_t>(isize), what + " (sparse indices)", &ibase, &istride);
  tmp.componentType = a.componentType;
  tmp.type = a.type;
  view_range(tmp, a.sparse.values.bufferView, static_cast<size_t>(a.sparse.values.byteOffset), n,
             static_cast<size_t>(ncomp * csize), what + " (sparse values)", &vbase, &vstride);
  for (size_t i = 0; i < n; ++i) {
    const uint32_t target = read_index(ibase + i * istride, itype);
    if (target >= a.count) throw BadInput(what + ": sparse index out of range");
    for (int c = 0; c < ncomp; ++c)
      out[target * ncomp + c] = component(vbase + i * vstride + static_cast<size_t>(c * csize),
                                          a.componentType, a.normalized);
  }
}

std::vector<uint32_t> AccessorReader::indices(int index, const std::string& what) const {
  if (index < 0 || static_cast<size_t>(index) >= model_.accessors.size())
    throw BadInput(what + ": index accessor " + std::to_string(index) + " does not exist");
  const tinygltf::Accessor& a = model_.accessors[index];
  const int t = a.componentType;
  if (a.type != TINYGLTF_TYPE_SCALAR ||
      (t != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE && t != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT &&
       t != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT))
    throw BadInput(what + ": indices must be unsigned integer scalars");
  if (a.sparse.isSparse) {  // rare for indices; go through the float path (exact below 2^24)
    int ncomp = 0;
    std::vector<float> f = floats(index, what, &ncomp);
    return std::vector<uint32_t>(f.begin(), f.end());
  }
  const std::string where = what + ": accessor " + std::to_string(index);
  const size_t isize = static_cast<size_t>(tinygltf::GetComponentSizeInBytes(static_cast<uint32_t>(t)));
  checked_mul(a.count, sizeof(uint32_t), where + " count x 4 bytes");
  const uint8_t* base = nullptr;
  size_t stride = 0;
  if (a.bufferView >= 0) view_range(a, a.bufferView, a.byteOffset, a.count, isize, where, &base, &stride);
  std::vector<uint32_t> out(a.count);
  if (base)
    for (size_t i = 0; i < a.count; ++i) out[i] = read_index(base + i * stride, t);
  return out;
}

}  // namespace foveart::engine::gltf
