#pragma once
/// @file run_main.h
/// @brief Runs a program body, turning any exception into one "PROGRAM: error: ..." line
/// on stderr and exit code 1, 2 for a vid::system::UsageError (docs/design.md §3: bad input never
/// crashes a program).

#include <functional>
#include <string>

namespace vid::app {

/// @brief Call body(); return its exit code, or 1 after printing the exception's message.
int run_main(const std::string& program, const std::function<int()>& body);

}  // namespace vid::app
