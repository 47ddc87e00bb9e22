#pragma once
/// @file lcm_input.h
/// @brief Checks of vid_live's LCM input before LCM sees it, so that a bad URL or log is one
/// line of ours (LCM prints its own lines, or reads garbage as "no events", otherwise).

#include <cstdint>
#include <string>

namespace vid::live {

/// @brief Validate an LCM URL given to @p flag: known provider (udpm, mpudpm, file, memq,
/// tcpq), udpm address multicast and port a number, known options with valid values (file:
/// speed >= 0, mode r/w/a, start_timestamp; udpm: ttl 0-255, recv_buf_size, transmit_only).
/// @p for_input: a file:// log must be read (mode r). Throws vid::app::UsageError (exit 2).
void check_lcm_url(const std::string& url, const std::string& flag, bool for_input);

/// @brief The file of a file:// URL (without the options).
std::string log_path(const std::string& url);

/// @brief An LCM event log walked event by event (headers and lengths only).
struct LogScan {
  std::uint64_t events = 0;       ///< whole events
  std::uint64_t whole_bytes = 0;  ///< bytes up to the end of the last whole event
  std::uint64_t size = 0;         ///< file size; > whole_bytes when the log is cut mid-event
};

/// @brief Scan the log at @p path. Throws std::runtime_error naming the file when it is
/// missing, empty, or has bytes that are not an LCM event where one should start.
LogScan scan_lcm_log(const std::string& path);

}  // namespace vid::live
