#pragma once
// A fresh directory per test under the build tree: TUBECAST_TEST_TMP/<suite>.<test>, emptied.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

namespace tc::test {

inline std::string testDir() {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    std::filesystem::path dir =
        std::filesystem::path(TUBECAST_TEST_TMP) / (std::string(info->test_suite_name()) + "." + info->name());
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    return dir.string();
}

}  // namespace tc::test
