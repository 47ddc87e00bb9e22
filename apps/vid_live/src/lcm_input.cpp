#include "live/lcm_input.h"

#include <fmt/format.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <stdexcept>
#include <vector>

#include "app/cli.h"

namespace vid::live {

namespace {

using app::UsageError;

bool parse_number(const std::string& s, double* v) {
  if (s.empty()) return false;
  char* end = nullptr;
  errno = 0;
  *v = std::strtod(s.c_str(), &end);
  return errno == 0 && end == s.c_str() + s.size();
}

void check_udpm_address(const std::string& url, const std::string& flag, const std::string& where) {
  // "239.255.76.67:7667": LCM's UDP multicast needs a multicast group (224.0.0.0/4).
  const auto colon = where.rfind(':');
  const std::string host = where.substr(0, colon);
  unsigned a = 0, b = 0, c = 0, d = 0;
  char tail = 0;
  if (!host.empty() && (std::sscanf(host.c_str(), "%u.%u.%u.%u%c", &a, &b, &c, &d, &tail) != 4 || a > 255 ||
                        b > 255 || c > 255 || d > 255))
    throw UsageError(fmt::format("{} {}: '{}' is not an IPv4 address", flag, url, host));
  if (!host.empty() && (a < 224 || a > 239))
    throw UsageError(fmt::format("{} {}: {} is not a multicast address (udpm needs 224.0.0.0 - 239.255.255.255, "
                                 "e.g. 239.255.76.67)",
                                 flag, url, host));
  double port = 0;
  if (colon != std::string::npos &&
      (!parse_number(where.substr(colon + 1), &port) || port < 1 || port > 65535 || port != static_cast<int>(port)))
    throw UsageError(fmt::format("{} {}: port '{}' is not a number in 1-65535", flag, url, where.substr(colon + 1)));
}

}  // namespace

std::string log_path(const std::string& url) {
  const std::string rest = url.substr(url.find("://") + 3);
  return rest.substr(0, rest.find('?'));
}

void check_lcm_url(const std::string& url, const std::string& flag, bool for_input) {
  const auto sep = url.find("://");
  if (sep == std::string::npos)
    throw UsageError(fmt::format("{} {}: not an LCM URL (PROVIDER://ADDRESS?OPTIONS, e.g. udpm://, file://LOG)", flag,
                                 url));
  const std::string provider = url.substr(0, sep);
  const std::string rest = url.substr(sep + 3);
  const std::string where = rest.substr(0, rest.find('?'));
  // Options LCM's providers understand, and a check of each value.
  const std::map<std::string, std::set<std::string>> keys = {
      {"udpm", {"ttl", "recv_buf_size", "transmit_only"}},
      {"mpudpm", {"ttl", "recv_buf_size", "transmit_only", "channel_range"}},
      {"file", {"speed", "mode", "start_timestamp"}},
      {"memq", {}},
      {"tcpq", {}}};
  const auto known = keys.find(provider);
  if (known == keys.end())
    throw UsageError(fmt::format("{} {}: unknown LCM provider '{}' (udpm, mpudpm, file, memq, tcpq)", flag, url,
                                 provider));
  if (provider == "udpm") check_udpm_address(url, flag, where);
  if (provider == "file" && where.empty()) throw UsageError(fmt::format("{} {}: no log file after file://", flag, url));
  std::string mode = "r";
  if (const auto q = rest.find('?'); q != std::string::npos) {
    std::size_t pos = q + 1;
    while (pos <= rest.size()) {
      std::size_t amp = rest.find('&', pos);
      if (amp == std::string::npos) amp = rest.size();
      const std::string kv = rest.substr(pos, amp - pos);
      pos = amp + 1;
      if (kv.empty()) continue;
      const auto eq = kv.find('=');
      const std::string key = kv.substr(0, eq), value = eq == std::string::npos ? "" : kv.substr(eq + 1);
      if (!known->second.count(key))
        throw UsageError(fmt::format("{} {}: unknown option '{}' for {}://", flag, url, key, provider));
      double v = 0;
      const bool number = parse_number(value, &v);
      auto bad = [&](const char* expected) {
        return UsageError(fmt::format("{} {}: option {}={}: expected {}", flag, url, key, value, expected));
      };
      if (key == "speed" && (!number || v < 0)) throw bad("a real-time factor >= 0 (0: as fast as read)");
      if (key == "mode" && value != "r" && value != "w" && value != "a") throw bad("r, w or a");
      if (key == "mode") mode = value;
      if (key == "start_timestamp" && (!number || v < 0)) throw bad("a timestamp [us] >= 0");
      if (key == "ttl" && (!number || v < 0 || v > 255 || v != static_cast<int>(v))) throw bad("an integer 0-255");
      if (key == "recv_buf_size" && (!number || v <= 0)) throw bad("a size in bytes > 0");
      if (key == "transmit_only" && value != "true" && value != "false") throw bad("true or false");
    }
  }
  if (provider == "file" && for_input && mode != "r")
    throw UsageError(fmt::format("{} {}: an input log is read (mode=r), not mode={}", flag, url, mode));
}

LogScan scan_lcm_log(const std::string& path) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec))
    throw std::runtime_error(path + ": no such LCM log (file:// input)");
  std::ifstream f(path, std::ios::binary);
  if (!f) throw std::runtime_error(path + ": cannot open the LCM log");
  LogScan s;
  s.size = std::filesystem::file_size(path, ec);
  if (s.size == 0) throw std::runtime_error(path + ": empty LCM log (no events)");
  // Event: magic 0xEDA1DA01, event number (8), timestamp (8), channel length (4), data length
  // (4), channel, data; integers big-endian.
  constexpr std::uint64_t kHeader = 28;
  unsigned char h[kHeader];
  auto be = [&](int at, int n) {
    std::uint64_t v = 0;
    for (int i = 0; i < n; ++i) v = (v << 8) | h[at + i];
    return v;
  };
  while (s.whole_bytes < s.size) {
    const std::uint64_t at = s.whole_bytes;
    if (s.size - at < kHeader) break;  // cut inside a header
    f.seekg(static_cast<std::streamoff>(at));
    if (!f.read(reinterpret_cast<char*>(h), kHeader))
      throw std::runtime_error(path + ": read error at byte " + std::to_string(at));
    if (be(0, 4) != 0xEDA1DA01u)
      throw std::runtime_error(fmt::format("{}: not an LCM event log (no event header at byte {}{})", path, at,
                                           at == 0 ? "" : fmt::format(", after {} events", s.events)));
    const std::uint64_t channel = be(20, 4), data = be(24, 4);
    if (channel == 0 || channel > 256)
      throw std::runtime_error(fmt::format("{}: corrupt LCM event at byte {} (channel name of {} bytes)", path, at,
                                           channel));
    if (at + kHeader + channel + data > s.size) break;  // cut inside the event
    s.whole_bytes = at + kHeader + channel + data;
    ++s.events;
  }
  return s;
}

}  // namespace vid::live
