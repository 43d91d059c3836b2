#pragma once
/// \file error.h
/// \brief The exceptions plantnbv throws. Apps catch `plantnbv::Error`, print its
/// message on one line and exit with code 1; the library never calls exit().

#include <stdexcept>
#include <string>

namespace plantnbv {

/// \brief Base of every error plantnbv throws on bad input or a failed operation.
class Error : public std::runtime_error {
public:
  using std::runtime_error::runtime_error;
};

/// \brief A parameter has a value outside its domain (the message names the value and
/// what was expected).
class InvalidArgumentError : public Error {
public:
  using Error::Error;
};

/// \brief A file could not be opened, read or written.
class IoError : public Error {
public:
  using Error::Error;
};

/// \brief A file or folder that should be read does not exist (Python's
/// FileNotFoundError).
class FileNotFoundError : public IoError {
public:
  using IoError::IoError;
};

/// \brief A file was read but its content is malformed, empty or of an unknown type.
class FormatError : public Error {
public:
  using Error::Error;
};

} // namespace plantnbv
