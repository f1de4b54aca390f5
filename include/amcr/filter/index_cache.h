// The proposal index's k-d tree in the table cache: with the
// tables read from the cache, building the tree over a large memory's
// entries (0.65 M for 70 prototypes) is most of the start-up. The tree is
// stored as one cache file (the layout of table_cache.h, payload: FLANN's
// own serialisation of the tree), named and keyed by the hash of the
// descriptors it indexes and the tree's settings, so a file can only be
// read back into the index whose entries it was built from. A refused file
// (damaged, stale, of another format) is reported and the tree built again.
#pragma once

#include <cstdint>
#include <memory>
#include <string>

#include <opencv2/core.hpp>

namespace cv
{
namespace flann
{
class Index;
}
}  // namespace cv

namespace amcr
{
class TableCache;

/// The key of a tree: the descriptors' bytes and shape, the leaf size, the
/// OpenCV version (FLANN's format) and the table format version.
std::uint64_t indexCacheKey(const cv::Mat& descriptors, int leaf_size);

/// The cache file of the tree with `key`.
std::string indexCacheName(std::uint64_t key);

/// The tree with `key` over `descriptors` (CV_32F, one row per entry, kept
/// alive by the caller as long as the index), read from `cache`; null when
/// there is no such file or it is refused (then `problem` says why).
std::unique_ptr<cv::flann::Index> readIndexTree(const TableCache& cache, std::uint64_t key,
                                                const cv::Mat& descriptors, std::string& problem);

/// Stores `tree` under `key`; returns why it could not ("" when stored or
/// the cache is not writable).
std::string writeIndexTree(const TableCache& cache, std::uint64_t key, const cv::flann::Index& tree);
}  // namespace amcr
