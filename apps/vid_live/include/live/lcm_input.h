#pragma once
/// @file lcm_input.h
/// @brief Checks of vid_live's LCM input before LCM sees it, so that a bad URL or log is one
/// line of ours (LCM prints its own lines, or reads garbage as "no events", otherwise).

#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace vid::live {

/// @brief Validate an LCM URL given to @p flag: known provider (udpm, mpudpm, file, memq,
/// tcpq), udpm address multicast and port a number, known options with valid values (file:
/// speed >= 0, mode r/w/a, start_timestamp; udpm: ttl 0-255, recv_buf_size, transmit_only).
/// @p for_input: a file:// log must be read (mode r). Throws vid::system::UsageError (exit 2).
void check_lcm_url(const std::string& url, const std::string& flag, bool for_input);

/// @brief The file of a file:// URL (without the options).
std::string log_path(const std::string& url);

/// @brief Bytes in the middle of a log that are not LCM events (a damaged block): LCM's file
/// provider skips them, searching for the next event's sync word.
struct DamagedSpan {
  std::uint64_t start = 0;         ///< first unreadable byte (where an event header should start)
  std::uint64_t end = 0;           ///< the next event header found (exclusive end of the span)
  std::int64_t events_lost = -1;   ///< gap in the event numbers around the span; -1: unknown
  std::int64_t first_lost = -1;    ///< the first missing event number (when events_lost > 0)
};

/// @brief An LCM event log walked event by event (headers and lengths only).
struct LogScan {
  std::uint64_t events = 0;       ///< whole events
  std::uint64_t whole_bytes = 0;  ///< bytes up to the end of the last whole event
  std::uint64_t size = 0;         ///< file size; > whole_bytes when the log is cut mid-event
  std::vector<DamagedSpan> damaged;  ///< unreadable spans between events, in file order
  /// @brief Events lost in all damaged spans (spans of unknown loss not counted).
  std::int64_t events_lost() const;
};

/// @brief Scan the log at @p path event by event: an event whose header is not where the
/// previous one ended is searched for at the next sync word, and the bytes in between are
/// recorded as a DamagedSpan (the events lost: the gap in the event numbers, which LCM's log
/// writers number 0, 1, 2, ...). Throws std::runtime_error naming the file when it is
/// missing, empty, does not start with an LCM event (not a log at all), has no event after a
/// damaged span, or has an event header with an impossible channel length.
LogScan scan_lcm_log(const std::string& path);

/// @brief One line describing the damaged spans of @p scan (byte offsets, events lost), for
/// the warning (read past them) or, with @p strict, the error.
std::string describe_damage(const std::string& path, const LogScan& scan, bool strict);

/// @brief Write the whole events of the log at @p path without its damaged spans to @p to: LCM's
/// file provider (1.3) stops at the first bytes after an event that are not the next event's
/// sync word ("Invalid header after log data"), so a damaged log is read through this copy.
/// Throws std::runtime_error naming @p to when it cannot be written.
void write_without_damage(const std::string& path, const LogScan& scan, const std::string& to);

/// @brief @p url (file://LOG?OPTIONS) with LOG replaced by @p path, the options kept.
std::string with_log_path(const std::string& url, const std::string& path);

/// @brief summary.json's input.lcm_log: file, size, events, damaged spans, events lost.
nlohmann::json log_scan_json(const std::string& path, const LogScan& scan);

}  // namespace vid::live
