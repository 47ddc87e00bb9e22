#include "app/run_main.h"

#include <cstdio>
#include <exception>
#include <string>

#include "app/cli.h"

namespace vid::app {

namespace {

/// The message on one line whatever it quotes (a multi-line YAML scalar, a file's bytes).
std::string one_line(const char* what) {
  std::string out;
  for (const char* c = what; *c != '\0'; ++c) {
    if (*c == '\n') out += "\\n";
    else if (*c == '\r' || *c == '\t') out += ' ';
    else out += *c;
  }
  return out;
}

}  // namespace

int run_main(const std::string& program, const std::function<int()>& body) {
  try {
    return body();
  } catch (const system::UsageError& e) {
    std::fprintf(stderr, "%s: error: %s\n", program.c_str(), one_line(e.what()).c_str());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s: error: %s\n", program.c_str(), one_line(e.what()).c_str());
  } catch (...) {
    std::fprintf(stderr, "%s: error: unknown exception\n", program.c_str());
  }
  return 1;
}

}  // namespace vid::app
