// The parameter file parser: bytes -> a .yaml file -> amcr::loadParams (yaml-cpp, the range
// checks, Params::validate). amcr::Error is an accepted answer; any other exception, an abort,
// a hang or a sanitizer report is a finding.
#include <cstddef>
#include <cstdint>

#include "amcr/base/errors.h"
#include "amcr/base/params.h"
#include "amcr/io/params_file.h"
#include "fuzz_input.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
  static const amcr_fuzz::ScratchDirectory scratch;
  const std::string path = scratch.write("params.yaml", data, size);
  try
  {
    const amcr::Params params = amcr::loadParams(path);
    params.validate();  // what loadParams returns must be valid
  }
  catch (const amcr::Error&)
  {
  }
  return 0;
}
