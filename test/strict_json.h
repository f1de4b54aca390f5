// Reads amcr_offline's output with nlohmann-json, as strictly as RFC 8259:
// json::parse refuses NaN, trailing characters, raw control characters in
// strings and lone surrogates; a key given twice in an object, which it
// would take (the last one wins), is refused here too.
#pragma once

#include <set>
#include <stdexcept>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace amcr_test
{
/// Parses the whole of `text` (one value, white space around it allowed).
/// Returns false with `error` set when it is not strict JSON.
inline bool parseStrictJson(const std::string& text, nlohmann::json& out, std::string& error)
{
  using Event = nlohmann::json::parse_event_t;
  std::vector<std::set<std::string>> keys_of_open_objects;
  const auto refuse_duplicate_keys = [&](int /*depth*/, Event event, nlohmann::json& parsed) {
    if (event == Event::object_start)
      keys_of_open_objects.emplace_back();
    else if (event == Event::object_end)
      keys_of_open_objects.pop_back();
    else if (event == Event::key && !keys_of_open_objects.back().insert(parsed.get<std::string>()).second)
      throw std::runtime_error("duplicate key " + parsed.dump());
    return true;
  };
  try
  {
    out = nlohmann::json::parse(text, refuse_duplicate_keys);
    return true;
  }
  catch (const std::exception& e)  // nlohmann::json::parse_error, or the duplicate key
  {
    error = e.what();
    return false;
  }
}

/// The member `key` of an object, or nullptr (also when `object` is no object).
inline const nlohmann::json* member(const nlohmann::json& object, const std::string& key)
{
  if (!object.is_object())
    return nullptr;
  const auto found = object.find(key);
  return found == object.end() ? nullptr : &*found;
}
}  // namespace amcr_test
