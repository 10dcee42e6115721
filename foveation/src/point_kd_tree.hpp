// nanoflann's k-d tree over 2D points (canvas pixels), for the neighbour tables and the
// point levels: the adaptor nanoflann asks for, and the tree at a distance precision.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include <glm/vec2.hpp>
#include <nanoflann.hpp>

namespace foveart::foveation {

struct PointCloud {
  const std::vector<glm::vec2>* pts;
  std::size_t kdtree_get_point_count() const { return pts->size(); }
  float kdtree_get_pt(std::size_t i, std::size_t dim) const { return (*pts)[i][int(dim)]; }
  template <class Box>
  bool kdtree_get_bbox(Box&) const { return false; }
};

template <class Distance>
using PointKdTree = nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<float, PointCloud, Distance>,
                                                        PointCloud, 2, std::uint32_t>;

}  // namespace foveart::foveation
