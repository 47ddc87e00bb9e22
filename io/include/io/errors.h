#pragma once
/// @file errors.h
/// @brief Typed exceptions of the io module. Messages name file and line, or file and key.

#include <stdexcept>
#include <string>

namespace vid::io {

/// @brief Malformed or missing dataset content; what() is "FILE:LINE: message" or "FILE: message".
class DatasetError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// @brief Invalid configuration; what() is "FILE: key 'a.b.c': message".
class ConfigError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace vid::io
