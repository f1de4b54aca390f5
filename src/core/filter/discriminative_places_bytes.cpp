// The look-alike pairs as bytes for the table cache (table_cache.h,
// discriminative_places_cache.cpp). The layout is the order of the fields
// below; kPlacesFormatVersion (discriminative_places_cache.h) must change
// with it. fromBytes() checks every index and count.
#include "amcr/filter/discriminative_places.h"

#include <cmath>
#include <string>

#include "amcr/base/errors.h"
#include "io/byte_stream.h"

namespace amcr
{
std::vector<std::uint8_t> DiscriminativePlaces::toBytes() const
{
  ByteWriter out;
  out.put<std::uint64_t>(pairs_.size());
  for (const AlikePair& pair : pairs_)
  {
    out.put<std::int32_t>(pair.a);
    out.put<std::int32_t>(pair.b);
    putMatx(out, pair.a_to_b);
    out.put<std::int32_t>(pair.confusions);
    out.put<std::uint64_t>(pair.places.size());
    for (const DiscriminativePlace& p : pair.places)
    {
      out.put(p.x);
      out.put(p.y);
      out.put(p.divergence);
    }
  }
  return out.take();
}

DiscriminativePlaces DiscriminativePlaces::fromBytes(const std::uint8_t* data, std::size_t size, int prototypes)
{
  ByteReader in(data, size);
  DiscriminativePlaces out;
  const std::size_t pairs = in.count(2 * sizeof(std::int32_t), "the look-alike pairs");
  for (std::size_t i = 0; i < pairs; ++i)
  {
    AlikePair pair;
    pair.a = in.get<std::int32_t>("a pair's first prototype");
    pair.b = in.get<std::int32_t>("a pair's second prototype");
    if (pair.a < 0 || pair.b < 0 || pair.a >= prototypes || pair.b >= prototypes || pair.a == pair.b)
      throw MemoryError("look-alike pair " + std::to_string(i) + " names prototypes " + std::to_string(pair.a) +
                        " and " + std::to_string(pair.b) + ", not two of the memory's " + std::to_string(prototypes));
    const AlikePair* previous = out.pairs_.empty() ? nullptr : &out.pairs_.back();
    if (previous && std::make_pair(previous->a, previous->b) >= std::make_pair(pair.a, pair.b))
      throw MemoryError("look-alike pair " + std::to_string(i) + " is out of order");
    pair.a_to_b = getMatx(in, "a pair's alignment");
    for (double value : pair.a_to_b.val)
      if (!std::isfinite(value))
        throw MemoryError("look-alike pair " + std::to_string(i) + " has an alignment that is not finite");
    pair.confusions = in.get<std::int32_t>("a pair's confusions");
    const std::size_t places = in.count(3 * sizeof(float), "a pair's places");
    for (std::size_t k = 0; k < places; ++k)
    {
      DiscriminativePlace p;
      p.x = in.get<float>("a place");
      p.y = in.get<float>("a place");
      p.divergence = in.get<float>("a place's divergence");
      if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.divergence))
        throw MemoryError("a place of look-alike pair " + std::to_string(i) + " is not finite");
      pair.places.push_back(p);
    }
    out.pairs_.push_back(std::move(pair));
  }
  if (in.left() != 0)
    throw MemoryError(std::to_string(in.left()) + " bytes are left after the look-alike pairs");
  return out;
}
}  // namespace amcr
