#include "live/lcm_input.h"

#include <fmt/format.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <set>
#include <stdexcept>
#include <vector>

#include "app/cli.h"

namespace vid::live {

namespace {

using system::UsageError;

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

namespace {

constexpr std::uint32_t kSync = 0xEDA1DA01u;

/// First offset >= @p from where the sync word starts (LCM's reader searches byte by byte), or
/// npos.
std::uint64_t find_sync(std::ifstream& f, std::uint64_t from, std::uint64_t size) {
  constexpr std::size_t kBlock = 1 << 16;
  std::vector<unsigned char> buf(kBlock + 3);
  for (std::uint64_t at = from; at + 4 <= size; at += kBlock) {
    const std::size_t n = static_cast<std::size_t>(std::min<std::uint64_t>(kBlock + 3, size - at));
    f.clear();
    f.seekg(static_cast<std::streamoff>(at));
    if (!f.read(reinterpret_cast<char*>(buf.data()), static_cast<std::streamsize>(n))) return std::string::npos;
    for (std::size_t i = 0; i + 4 <= n; ++i)
      if (buf[i] == 0xED && buf[i + 1] == 0xA1 && buf[i + 2] == 0xDA && buf[i + 3] == 0x01) return at + i;
  }
  return std::string::npos;
}

}  // namespace

std::int64_t LogScan::events_lost() const {
  std::int64_t n = 0;
  // Saturates: gaps come from event numbers in the file, which a damaged log may make huge.
  for (const DamagedSpan& d : damaged)
    if (__builtin_add_overflow(n, std::max<std::int64_t>(d.events_lost, 0), &n))
      return std::numeric_limits<std::int64_t>::max();
  return n;
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
  // Event: sync word 0xEDA1DA01, event number (8), timestamp (8), channel length (4), data
  // length (4), channel, data; integers big-endian.
  constexpr std::uint64_t kHeader = 28;
  unsigned char h[kHeader];
  auto be = [&](int at, int n) {
    std::uint64_t v = 0;
    for (int i = 0; i < n; ++i) v = (v << 8) | h[at + i];
    return v;
  };
  std::uint64_t at = 0;
  std::int64_t last_number = -1;
  bool resynced = false;
  while (at < s.size) {
    if (s.size - at < kHeader) break;  // cut inside a header
    f.clear();
    f.seekg(static_cast<std::streamoff>(at));
    if (!f.read(reinterpret_cast<char*>(h), kHeader))
      throw std::runtime_error(path + ": read error at byte " + std::to_string(at));
    if (be(0, 4) != kSync) {
      // Not a log at all when it does not start with an event; in the middle, LCM's reader
      // skips to the next sync word, and so does the scan, recording the span.
      if (s.events == 0)
        throw std::runtime_error(fmt::format("{}: not an LCM event log (no event header at byte {})", path, at));
      const std::uint64_t next = find_sync(f, at + 1, s.size);
      if (next == std::string::npos)
        throw std::runtime_error(fmt::format("{}: not an LCM event log (no event header at byte {}, after {} events, "
                                             "nor anywhere after it)",
                                             path, at, s.events));
      s.damaged.push_back(DamagedSpan{at, next, -1, -1});
      at = next;
      resynced = true;
      continue;
    }
    const std::uint64_t channel = be(20, 4), data = be(24, 4);
    if (channel == 0 || channel > 256)
      throw std::runtime_error(fmt::format("{}: corrupt LCM event at byte {} (channel name of {} bytes)", path, at,
                                           channel));
    if (at + kHeader + channel + data > s.size) break;  // cut inside the event
    const auto number = static_cast<std::int64_t>(be(4, 8));
    // Event numbers come from the file: a damaged one may be any int64, so the gap is computed
    // without overflow and a gap that does not fit stays "unknown".
    std::int64_t gap = 0;
    if (resynced && number > last_number && !__builtin_sub_overflow(number, last_number, &gap)) {
      s.damaged.back().events_lost = gap - 1;
      s.damaged.back().first_lost = last_number + 1;
    }
    resynced = false;
    last_number = number;
    at += kHeader + channel + data;
    s.whole_bytes = at;
    ++s.events;
  }
  return s;
}

std::string describe_damage(const std::string& path, const LogScan& scan, bool strict) {
  if (scan.damaged.empty()) return "";
  auto lost = [](const DamagedSpan& d) {
    if (d.events_lost < 0) return std::string("an unknown number of events lost");
    if (d.events_lost == 0) return std::string("no event lost");
    return fmt::format("{} event{} lost, numbers {}-{}", d.events_lost, d.events_lost == 1 ? "" : "s", d.first_lost,
                       d.first_lost + d.events_lost - 1);
  };
  const DamagedSpan& d0 = scan.damaged.front();
  if (strict)
    return fmt::format("{}: damaged LCM log: no event header at byte {} (the next at byte {}: {}{}); --strict makes "
                       "this an error (without it: read past, one warning)",
                       path, d0.start, d0.end, lost(d0),
                       scan.damaged.size() > 1 ? fmt::format("; {} damaged spans in all", scan.damaged.size()) : "");
  std::string spans;
  const std::size_t shown = std::min<std::size_t>(scan.damaged.size(), 5);
  for (std::size_t i = 0; i < shown; ++i) {
    const DamagedSpan& d = scan.damaged[i];
    spans += fmt::format("{}{}-{}: {}", i ? "; " : "", d.start, d.end, lost(d));
  }
  if (shown < scan.damaged.size()) spans += fmt::format("; and {} more", scan.damaged.size() - shown);
  const std::string where = scan.damaged.size() == 1 ? "at bytes " : fmt::format("at {} places: ", scan.damaged.size());
  return fmt::format("{}: unreadable bytes skipped (not LCM events) {}{}; {} events lost in all, {} read (summary.json "
                     "input.lcm_log; --strict makes this an error)",
                     path, where, spans, scan.events_lost(), scan.events);
}

void write_without_damage(const std::string& path, const LogScan& scan, const std::string& to) {
  std::ifstream in(path, std::ios::binary);
  std::ofstream out(to, std::ios::binary | std::ios::trunc);
  if (!in) throw std::runtime_error(path + ": cannot open the LCM log");
  if (!out) throw std::runtime_error(to + ": cannot write a copy of " + path + " without its damaged spans");
  std::vector<char> buf(1 << 20);
  auto copy = [&](std::uint64_t from, std::uint64_t until) {
    in.clear();
    in.seekg(static_cast<std::streamoff>(from));
    for (std::uint64_t left = until - from; left > 0;) {
      const auto n = static_cast<std::streamsize>(std::min<std::uint64_t>(left, buf.size()));
      if (!in.read(buf.data(), n) || !out.write(buf.data(), n))
        throw std::runtime_error(to + ": cannot write a copy of " + path + " without its damaged spans");
      left -= static_cast<std::uint64_t>(n);
    }
  };
  std::uint64_t at = 0;
  for (const DamagedSpan& d : scan.damaged) {
    copy(at, d.start);
    at = d.end;
  }
  copy(at, scan.whole_bytes);
  out.close();
  if (!out) throw std::runtime_error(to + ": cannot write a copy of " + path + " without its damaged spans");
}

std::string with_log_path(const std::string& url, const std::string& path) {
  const auto q = url.find('?');
  return "file://" + path + (q == std::string::npos ? "" : url.substr(q));
}

nlohmann::json log_scan_json(const std::string& path, const LogScan& scan) {
  nlohmann::json spans = nlohmann::json::array();
  std::uint64_t skipped = 0;
  for (const DamagedSpan& d : scan.damaged) {
    skipped += d.end - d.start;
    spans.push_back({{"start_byte", d.start}, {"end_byte", d.end}, {"bytes", d.end - d.start},
                     {"events_lost", d.events_lost >= 0 ? nlohmann::json(d.events_lost) : nlohmann::json(nullptr)}});
  }
  return {{"path", path},          {"size_bytes", scan.size},      {"events", scan.events},
          {"damaged_spans", spans}, {"bytes_skipped", skipped},     {"events_lost", scan.events_lost()}};
}

}  // namespace vid::live
