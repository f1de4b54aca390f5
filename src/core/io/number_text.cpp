// Number literals of a parameter file (number_text.h).
#include "number_text.h"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <functional>
#include <limits>
#include <locale>
#include <sstream>

#include "amcr/base/errors.h"

namespace amcr
{
namespace
{
constexpr long long kLargestExactInteger = 9007199254740992LL;  // 2^53

/// Whole numbers as amcr has always read them (strtoll with base 0, as YAML
/// 1.1 and rosparam do too): 42, -7, 0x1F hexadecimal, 017 octal.
bool isWholeNumber(const std::string& text)
{
  const std::size_t at = !text.empty() && (text[0] == '+' || text[0] == '-') ? 1 : 0;
  const auto digits = [&](std::size_t from, const std::function<bool(unsigned char)>& is_digit) {
    return text.size() > from && std::all_of(text.begin() + from, text.end(), is_digit);
  };
  if (text.compare(at, 2, "0x") == 0 || text.compare(at, 2, "0X") == 0)
    return digits(at + 2, [](unsigned char c) { return std::isxdigit(c) != 0; });
  if (text.compare(at, 1, "0") == 0)
    return digits(at, [](unsigned char c) { return c >= '0' && c <= '7'; });
  return digits(at, [](unsigned char c) { return std::isdigit(c) != 0; });
}

/// Decimals with a point or an exponent: 2.5, .5, 5., 1e-3, -2.5E+2.
bool isDecimal(const std::string& text)
{
  std::size_t at = !text.empty() && (text[0] == '+' || text[0] == '-') ? 1 : 0;
  const auto skipDigits = [&]() {
    const std::size_t from = at;
    while (at < text.size() && std::isdigit(static_cast<unsigned char>(text[at])))
      ++at;
    return at - from;
  };
  std::size_t digits = skipDigits();
  const bool point = at < text.size() && text[at] == '.';
  if (point)
  {
    ++at;
    digits += skipDigits();
  }
  if (digits == 0)
    return false;
  const bool exponent = at < text.size() && (text[at] == 'e' || text[at] == 'E');
  if (exponent)
  {
    at += at + 1 < text.size() && (text[at + 1] == '+' || text[at + 1] == '-') ? 2 : 1;
    if (skipDigits() == 0)
      return false;
  }
  return at == text.size() && (point || exponent);
}
}  // namespace

std::optional<double> numberFromText(const std::string& text, const std::string& name)
{
  if (isWholeNumber(text))
  {
    errno = 0;
    const long long value = std::strtoll(text.c_str(), nullptr, 0);
    if (errno == ERANGE || value > kLargestExactInteger || value < -kLargestExactInteger)
      throw ParameterError("parameter '" + name + "' = " + text +
                           " is beyond 2^53 = 9007199254740992, the largest whole number read exactly");
    return static_cast<double>(value);
  }
  const std::string unsigned_text = text.substr(!text.empty() && (text[0] == '+' || text[0] == '-') ? 1 : 0);
  if (unsigned_text == ".inf" || unsigned_text == ".Inf" || unsigned_text == ".INF")
    return text[0] == '-' ? -HUGE_VAL : HUGE_VAL;
  if (text == ".nan" || text == ".NaN" || text == ".NAN")
    return std::numeric_limits<double>::quiet_NaN();
  if (!isDecimal(text))
    return std::nullopt;
  std::istringstream in(text);  // the "C" locale's decimal point, whatever the program's locale
  in.imbue(std::locale::classic());
  double value = 0.0;
  in >> value;
  return in.fail() ? (text[0] == '-' ? -HUGE_VAL : HUGE_VAL) : value;  // only an overflow fails here
}
}  // namespace amcr
