// Exceptions thrown by the amcr core library. The library never calls exit()
// or abort(): every failure is one of these, with a message naming what was
// wrong, so a nodelet or runner can report it and carry on.
#pragma once

#include <stdexcept>
#include <string>

namespace amcr
{
/// Base class of every error the library throws.
class Error : public std::runtime_error
{
public:
  explicit Error(const std::string& what) : std::runtime_error(what) {}
};

/// A parameter is outside its allowed range or unknown.
class ParameterError : public Error
{
public:
  explicit ParameterError(const std::string& what) : Error(what) {}
};

/// An input image cannot be used (empty, unsupported type).
class InputError : public Error
{
public:
  explicit InputError(const std::string& what) : Error(what) {}
};

/// The prototype memory cannot be built (missing directory, no usable prototype).
class MemoryError : public Error
{
public:
  explicit MemoryError(const std::string& what) : Error(what) {}
};
}  // namespace amcr
