// The parameter file: config/amcr.yaml and the files a user writes like it,
// read over the defaults of amcr::Params (params.h) through its table by name.
#pragma once

#include <string>

#include "amcr/base/params.h"

namespace amcr
{
/// Reads parameters from a YAML file (yaml-cpp) over the defaults in
/// `params`. Unknown keys, keys given twice and values out of range throw
/// ParameterError naming the file and the line, as does a file that cannot
/// be read (with the reason: no such file, permission denied, a directory)
/// or parsed (with the line and the reason), a second document in it, or
/// lists and maps nested deeper than 8. Old files' OpenCV header `%YAML:1.0`
/// is read as a comment. A quoted value is a word; true and false set a
/// numeric parameter to 1 and 0. Whole numbers are read from their text
/// (0x1F hexadecimal and 017 octal as strtoll reads them), so none wraps at
/// 32 bits; a whole number beyond 2^53 (which a double does not hold
/// exactly) is refused.
Params loadParams(const std::string& yaml_path, Params params = Params());
}  // namespace amcr
