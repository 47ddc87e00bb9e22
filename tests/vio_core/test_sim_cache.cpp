// Cached simulator folders (ensure_sim_dataset, docs/testing.md "Cached inputs"): reused only
// when made by the same vid_sim binary, scenario text, seed and duration; a folder made by
// anything else (or before the stamp existed) is regenerated instead of testing old output.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "sim_system.h"

namespace {
using vid::test::ensure_sim_dataset;

std::string slurp(const std::filesystem::path& p) {
  std::ifstream in(p);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

TEST(SimCache, StaleFolderIsRegenerated) {
  const auto out = ensure_sim_dataset("euroc_like_short", 97, 1.5);  // 1.5 s: cheap
  const std::string made_by = slurp(out / "made_by.txt");
  ASSERT_NE(made_by.find("vid_sim "), std::string::npos);
  ASSERT_NE(made_by.find("seed 97"), std::string::npos);
  std::ofstream(out / "marker") << "kept";
  EXPECT_EQ(ensure_sim_dataset("euroc_like_short", 97, 1.5), out);
  EXPECT_TRUE(std::filesystem::exists(out / "marker")) << "an unchanged folder is reused";
  // Another simulator build made it, or no stamp at all (a folder from before stamps).
  for (const bool remove : {false, true}) {
    std::ofstream(out / "marker") << "old output";
    if (remove) {
      std::filesystem::remove(out / "made_by.txt");
    } else {
      std::ofstream(out / "made_by.txt") << "vid_sim 0000000000000000\n";
    }
    EXPECT_EQ(ensure_sim_dataset("euroc_like_short", 97, 1.5), out);
    EXPECT_FALSE(std::filesystem::exists(out / "marker")) << "old output reused";
    EXPECT_EQ(slurp(out / "made_by.txt"), made_by);
    EXPECT_TRUE(std::filesystem::exists(out / "mav0" / "feat0" / "data.csv"));
  }
}

}  // namespace
