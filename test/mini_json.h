// A strict JSON parser (RFC 8259) for tests that check amcr_offline's output
// is well formed. Small on purpose: no JSON library is a dependency.
#pragma once

#include <cstdlib>
#include <string>
#include <utility>
#include <vector>

namespace amcr_test
{
struct Json
{
  enum class Type
  {
    kNull,
    kBool,
    kNumber,
    kString,
    kArray,
    kObject
  };
  Type type = Type::kNull;
  bool boolean = false;
  double number = 0.0;
  std::string string;
  std::vector<Json> array;
  std::vector<std::pair<std::string, Json>> object;  // in document order

  /// The member `key` of an object, or nullptr.
  const Json* get(const std::string& key) const
  {
    for (const auto& member : object)
      if (member.first == key)
        return &member.second;
    return nullptr;
  }
  bool isNumber() const { return type == Type::kNumber; }
  bool isString() const { return type == Type::kString; }
  bool isArray() const { return type == Type::kArray; }
  bool isObject() const { return type == Type::kObject; }
};

class JsonParser
{
public:
  /// Parses the whole of `text` (one value, surrounded by optional white
  /// space). Returns false with `error` set on any deviation from the grammar.
  static bool parse(const std::string& text, Json& out, std::string& error)
  {
    JsonParser parser(text);
    if (!parser.value(out, 0) || (parser.space(), parser.pos_ != text.size()))
    {
      error = (parser.error_.empty() ? "trailing characters" : parser.error_) + " at offset " +
              std::to_string(parser.pos_);
      return false;
    }
    return true;
  }

private:
  explicit JsonParser(const std::string& text) : text_(text) {}

  bool fail(const std::string& what)
  {
    if (error_.empty())
      error_ = what;
    return false;
  }
  void space()
  {
    while (pos_ < text_.size() &&
           (text_[pos_] == ' ' || text_[pos_] == '\t' || text_[pos_] == '\n' || text_[pos_] == '\r'))
      ++pos_;
  }
  bool literal(const char* word)
  {
    const std::string w(word);
    if (text_.compare(pos_, w.size(), w) != 0)
      return fail("bad literal");
    pos_ += w.size();
    return true;
  }
  static bool digit(char c) { return c >= '0' && c <= '9'; }

  bool value(Json& out, int depth)
  {
    if (depth > 64)
      return fail("nesting too deep");
    space();
    if (pos_ >= text_.size())
      return fail("unexpected end");
    const char c = text_[pos_];
    if (c == '{')
      return objectValue(out, depth);
    if (c == '[')
      return arrayValue(out, depth);
    if (c == '"')
    {
      out.type = Json::Type::kString;
      return stringValue(out.string);
    }
    if (c == 't' || c == 'f')
    {
      out.type = Json::Type::kBool;
      out.boolean = c == 't';
      return literal(c == 't' ? "true" : "false");
    }
    if (c == 'n')
    {
      out.type = Json::Type::kNull;
      return literal("null");
    }
    return numberValue(out);
  }

  bool numberValue(Json& out)
  {
    const std::size_t start = pos_;
    if (pos_ < text_.size() && text_[pos_] == '-')
      ++pos_;
    if (pos_ >= text_.size() || !digit(text_[pos_]))
      return fail("bad number");
    if (text_[pos_] == '0')
      ++pos_;
    else
      while (pos_ < text_.size() && digit(text_[pos_]))
        ++pos_;
    if (pos_ < text_.size() && text_[pos_] == '.')
    {
      ++pos_;
      if (pos_ >= text_.size() || !digit(text_[pos_]))
        return fail("bad fraction");
      while (pos_ < text_.size() && digit(text_[pos_]))
        ++pos_;
    }
    if (pos_ < text_.size() && (text_[pos_] == 'e' || text_[pos_] == 'E'))
    {
      ++pos_;
      if (pos_ < text_.size() && (text_[pos_] == '+' || text_[pos_] == '-'))
        ++pos_;
      if (pos_ >= text_.size() || !digit(text_[pos_]))
        return fail("bad exponent");
      while (pos_ < text_.size() && digit(text_[pos_]))
        ++pos_;
    }
    out.type = Json::Type::kNumber;
    out.number = std::strtod(text_.substr(start, pos_ - start).c_str(), nullptr);
    return true;
  }

  static void appendUtf8(std::string& out, unsigned code)
  {
    if (code < 0x80)
      out += static_cast<char>(code);
    else if (code < 0x800)
    {
      out += static_cast<char>(0xC0 | (code >> 6));
      out += static_cast<char>(0x80 | (code & 0x3F));
    }
    else if (code < 0x10000)
    {
      out += static_cast<char>(0xE0 | (code >> 12));
      out += static_cast<char>(0x80 | ((code >> 6) & 0x3F));
      out += static_cast<char>(0x80 | (code & 0x3F));
    }
    else
    {
      out += static_cast<char>(0xF0 | (code >> 18));
      out += static_cast<char>(0x80 | ((code >> 12) & 0x3F));
      out += static_cast<char>(0x80 | ((code >> 6) & 0x3F));
      out += static_cast<char>(0x80 | (code & 0x3F));
    }
  }

  bool hex4(unsigned& code)
  {
    if (pos_ + 4 > text_.size())
      return fail("short \\u escape");
    code = 0;
    for (int i = 0; i < 4; ++i)
    {
      const char h = text_[pos_++];
      code <<= 4;
      if (h >= '0' && h <= '9')
        code |= h - '0';
      else if (h >= 'a' && h <= 'f')
        code |= h - 'a' + 10;
      else if (h >= 'A' && h <= 'F')
        code |= h - 'A' + 10;
      else
        return fail("bad \\u escape");
    }
    return true;
  }

  bool stringValue(std::string& out)
  {
    ++pos_;  // opening quote
    out.clear();
    while (true)
    {
      if (pos_ >= text_.size())
        return fail("unterminated string");
      const unsigned char c = static_cast<unsigned char>(text_[pos_++]);
      if (c == '"')
        return true;
      if (c < 0x20)
        return fail("raw control character in string");
      if (c != '\\')
      {
        out += static_cast<char>(c);
        continue;
      }
      if (pos_ >= text_.size())
        return fail("unterminated escape");
      const char e = text_[pos_++];
      switch (e)
      {
        case '"':
        case '\\':
        case '/':
          out += e;
          break;
        case 'b':
          out += '\b';
          break;
        case 'f':
          out += '\f';
          break;
        case 'n':
          out += '\n';
          break;
        case 'r':
          out += '\r';
          break;
        case 't':
          out += '\t';
          break;
        case 'u':
        {
          unsigned code = 0;
          if (!hex4(code))
            return false;
          if (code >= 0xD800 && code <= 0xDBFF)
          {
            unsigned low = 0;
            if (text_.compare(pos_, 2, "\\u") != 0)
              return fail("lone surrogate");
            pos_ += 2;
            if (!hex4(low) || low < 0xDC00 || low > 0xDFFF)
              return fail("bad surrogate pair");
            code = 0x10000 + ((code - 0xD800) << 10) + (low - 0xDC00);
          }
          else if (code >= 0xDC00 && code <= 0xDFFF)
            return fail("lone surrogate");
          appendUtf8(out, code);
          break;
        }
        default:
          return fail("bad escape");
      }
    }
  }

  bool arrayValue(Json& out, int depth)
  {
    out.type = Json::Type::kArray;
    ++pos_;
    space();
    if (pos_ < text_.size() && text_[pos_] == ']')
    {
      ++pos_;
      return true;
    }
    while (true)
    {
      Json element;
      if (!value(element, depth + 1))
        return false;
      out.array.push_back(std::move(element));
      space();
      if (pos_ >= text_.size())
        return fail("unterminated array");
      const char c = text_[pos_++];
      if (c == ']')
        return true;
      if (c != ',')
        return fail("expected , or ]");
    }
  }

  bool objectValue(Json& out, int depth)
  {
    out.type = Json::Type::kObject;
    ++pos_;
    space();
    if (pos_ < text_.size() && text_[pos_] == '}')
    {
      ++pos_;
      return true;
    }
    while (true)
    {
      space();
      if (pos_ >= text_.size() || text_[pos_] != '"')
        return fail("expected a key");
      std::string key;
      if (!stringValue(key))
        return false;
      if (out.get(key) != nullptr)
        return fail("duplicate key " + key);
      space();
      if (pos_ >= text_.size() || text_[pos_] != ':')
        return fail("expected :");
      ++pos_;
      Json member;
      if (!value(member, depth + 1))
        return false;
      out.object.emplace_back(std::move(key), std::move(member));
      space();
      if (pos_ >= text_.size())
        return fail("unterminated object");
      const char c = text_[pos_++];
      if (c == '}')
        return true;
      if (c != ',')
        return fail("expected , or }");
    }
  }

  const std::string& text_;
  std::size_t pos_ = 0;
  std::string error_;
};
}  // namespace amcr_test
