#include "io/number_format.h"

#include <charconv>
#include <stdexcept>

namespace vid::io {

std::string format_double(double v) {
  char buf[64];
  const auto [ptr, ec] = std::to_chars(buf, buf + sizeof(buf), v);
  if (ec != std::errc()) throw std::runtime_error("format_double: conversion failed");
  return std::string(buf, ptr);
}

std::string format_list(const std::vector<double>& v) {
  std::string out = "[";
  for (std::size_t i = 0; i < v.size(); ++i) {
    if (i > 0) out += ", ";
    out += format_double(v[i]);
  }
  return out + "]";
}

}  // namespace vid::io
