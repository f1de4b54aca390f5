// The numbers of a parameter file as amcr reads them (params_file.cpp).
#pragma once

#include <optional>
#include <string>

namespace amcr
{
/// The value of `text` when it is a number: a whole number as amcr has always
/// read it (strtoll with base 0, as YAML 1.1 and rosparam read it too: 42,
/// -7, 0x1F hexadecimal, 017 octal), a decimal with a point or an exponent
/// (2.5, .5, 5., 1e-3) or YAML's .inf and .nan; none for any other text. A
/// whole number beyond 2^53, which a double does not hold exactly, throws
/// ParameterError naming the parameter `name`.
std::optional<double> numberFromText(const std::string& text, const std::string& name);
}  // namespace amcr
