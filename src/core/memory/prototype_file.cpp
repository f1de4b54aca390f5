#include "amcr/memory/prototype_file.h"

#include "amcr/base/content_hash.h"
#include "amcr/base/errors.h"
#include "amcr/io/image_file.h"

namespace amcr
{
LoadedPrototype loadPrototypeFile(const std::string& path, const std::string& label, const MemoryParams& params,
                                  const TableCache& cache, const std::string& instance)
{
  LoadedPrototype loaded;
  try
  {
    // The file's bytes name the image: a hit needs no decoding.
    const std::vector<unsigned char> bytes = readImageFileBytes(path);
    const std::uint64_t image_hash = hashBytes(bytes.data(), bytes.size());
    const std::uint64_t key = tableCacheKey(image_hash, params);
    TableCache::Found found = cache.read(label, image_hash, key, instance);
    if (found.prototype)
    {
      loaded.prototype = std::move(found.prototype);
      loaded.from_cache = true;
      return loaded;
    }
    if (!found.problem.empty())
    {
      loaded.refused = true;
      loaded.warnings.push_back("table cache: '" + cache.path(label, image_hash) + "' refused (" + found.problem +
                                "); the table of '" + path + "' is built again and the file replaced");
    }
    auto prototype = std::make_shared<const Prototype>(label, decodeImageFile(bytes, path), params.prototype_size,
                                                      params.edge_threshold, params.blur_sigma, params.table_stride,
                                                      instance, params.edge_full_strength, params.keep_polarity);
    const std::string not_written = cache.write(label, image_hash, key, *prototype);
    if (!not_written.empty())
      loaded.warnings.push_back("table cache: the table of '" + path + "' is not stored: " + not_written);
    loaded.written = cache.writable() && not_written.empty();
    loaded.prototype = std::move(prototype);
  }
  catch (const InputError& e)  // the file
  {
    loaded.warnings.push_back("skipped '" + path + "': " + e.what());
  }
  catch (const MemoryError& e)  // the image
  {
    loaded.warnings.push_back("skipped '" + path + "': " + e.what());
  }
  return loaded;
}
}  // namespace amcr
