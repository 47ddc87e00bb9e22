/// @file lcm_fuzz.cpp
/// @brief libFuzzer target of the LCM input path of vid_live: payload decoding and checks
/// (io/src/lcm/lcm_convert.cpp: decode<T>, from_lcm, validate_image) and the input checks of
/// apps/vid_live/src/lcm_input.cpp (an LCM event log scanned by scan_lcm_log, a URL checked by
/// check_lcm_url). Expected outcomes: lcm_io::DecodeError, system::UsageError, and the plain
/// std::runtime_error scan_lcm_log documents; anything else is a bug.
///
/// Input: byte 0 mod 10 picks what the rest is (the digits '0'..'9' do): 0 imu_t, 1 image_t,
/// 2 rotor_speeds_t, 3 thrust_t, 4 state_t, 5 status_t, 6 force_t, 7 an LCM log file,
/// 8 an input URL, 9 an output URL.

#include <string>
#include <typeinfo>

#include "fuzz_util.h"
#include "io/lcm/lcm_convert.h"
#include "live/lcm_input.h"
#include "vid_system/usage_error.h"

namespace lio = vid::lcm_io;

namespace {

void run(int kind, const std::uint8_t* p, std::size_t n) {
  const std::string ch = "CH";
  switch (kind) {
    case 0: (void)lio::from_lcm(lio::decode<vid::imu_t>(p, n, ch), ch); break;
    case 1: lio::validate_image(lio::decode<vid::image_t>(p, n, ch), ch, 2); break;
    case 2: {
      const auto m = lio::decode<vid::rotor_speeds_t>(p, n, ch);
      (void)lio::from_lcm(m, ch, 0, "");
      (void)lio::from_lcm(m, ch, 4, "rpm");
      break;
    }
    case 3: (void)lio::from_lcm(lio::decode<vid::thrust_t>(p, n, ch), ch); break;
    case 4: (void)lio::decode<vid::state_t>(p, n, ch); break;
    case 5: (void)lio::decode<vid::status_t>(p, n, ch); break;
    case 6: (void)lio::decode<vid::force_t>(p, n, ch); break;
    case 7: {
      const auto path = vid::fuzz::scratch_dir() / "events.lcm";
      vid::fuzz::write_file(path, std::string_view(reinterpret_cast<const char*>(p), n));
      try {
        (void)vid::live::scan_lcm_log(path.string());
      } catch (const std::runtime_error& e) {
        if (typeid(e) != typeid(std::runtime_error)) throw;  // only the documented plain type
      }
      break;
    }
    default: {
      const std::string url(reinterpret_cast<const char*>(p), n);
      vid::live::check_lcm_url(url, "--lcm-url", kind == 8);
      if (url.find("://") != std::string::npos) (void)vid::live::log_path(url);
    }
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  try {
    run(data[0] % 10, data + 1, size - 1);
  } catch (const lio::DecodeError&) {
  } catch (const vid::system::UsageError&) {
  }
  return 0;
}
