#include "app/run_main.h"

#include <cstdio>
#include <exception>

#include "app/cli.h"

namespace vid::app {

int run_main(const std::string& program, const std::function<int()>& body) {
  try {
    return body();
  } catch (const UsageError& e) {
    std::fprintf(stderr, "%s: error: %s\n", program.c_str(), e.what());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s: error: %s\n", program.c_str(), e.what());
  } catch (...) {
    std::fprintf(stderr, "%s: error: unknown exception\n", program.c_str());
  }
  return 1;
}

}  // namespace vid::app
