#pragma once
/// @file lcm_loop.h
/// @brief Drives an LCM instance's handle loop until the input ends: end of a file:// log,
/// a stop request, or (live transports) no message for an idle timeout.

#include <atomic>
#include <functional>
#include <string>

#include <lcm/lcm-cpp.hpp>

namespace vid::live {

/// @brief True for file:// URLs (LCM event logs read by LCM's file provider).
bool is_log_url(const std::string& url);
/// @brief True for a file:// URL with speed=0 (played as fast as the reader takes messages).
bool is_fast_log_url(const std::string& url);

/// @brief Handle messages until the end of input.
/// @param stop  polled between messages: true ends the loop ("stopped")
/// @param idle_timeout_s  live transports: stop after this long without messages once one
///                        has arrived (<= 0: only @p stop ends the loop)
/// @param received        incremented by the caller's handlers (used for the idle timeout)
/// @return "eof", "stopped" or "idle"
std::string run_lcm_loop(lcm::LCM& lcm, const std::string& url, const std::function<bool()>& stop,
                         double idle_timeout_s, const std::atomic<long>& received);

}  // namespace vid::live
