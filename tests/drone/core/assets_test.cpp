// Where the program finds its assets (drone/core/assets.hpp): the variable, then the installed
// folder beside the program, then the source tree.
#include "drone/core/assets.hpp"

#include <gtest/gtest.h>

#include <filesystem>

namespace gs {
namespace {
namespace fs = std::filesystem;

struct TempPrefix {
    fs::path root =
        fs::temp_directory_path() /
        ("gs_assets_test_" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) +
         "_" + ::testing::UnitTest::GetInstance()->current_test_info()->name());
    TempPrefix() { fs::create_directories(root / "bin"); }
    ~TempPrefix() {
        std::error_code ec;
        fs::remove_all(root, ec);
    }
};

TEST(Assets, TheVariableWinsWhenSet) {
    TempPrefix p;
    fs::create_directories(p.root / "share/ardrone-gs");
    auto where = locate_assets("/somewhere/else", p.root / "bin/ardrone-gs", "/src/assets");
    EXPECT_EQ(where.dir, fs::path("/somewhere/else"));
    EXPECT_EQ(where.origin, AssetsOrigin::Environment);
}

TEST(Assets, AnEmptyVariableIsNotSet) {
    auto where = locate_assets("", "/nonexistent/bin/ardrone-gs", "/src/assets");
    EXPECT_EQ(where.origin, AssetsOrigin::SourceTree);
}

TEST(Assets, AnInstalledProgramReadsTheFolderBesideItself) {
    TempPrefix p;
    fs::create_directories(p.root / "share/ardrone-gs");
    auto where = locate_assets(nullptr, p.root / "bin/ardrone-gs", "/src/assets");
    EXPECT_EQ(where.origin, AssetsOrigin::Installed);
    EXPECT_TRUE(fs::equivalent(where.dir, p.root / "share/ardrone-gs"));
    EXPECT_EQ(where.dir, where.dir.lexically_normal());  // no "bin/.." left in what is shown
}

TEST(Assets, AProgramInItsBuildTreeReadsTheSourceTree) {
    TempPrefix p;  // bin/ exists, share/ardrone-gs does not
    auto where = locate_assets(nullptr, p.root / "bin/ardrone-gs", "/src/assets");
    EXPECT_EQ(where.origin, AssetsOrigin::SourceTree);
    EXPECT_EQ(where.dir, fs::path("/src/assets"));
    // The test programs themselves run from the build tree and find the source tree's assets.
    EXPECT_TRUE(fs::exists(assets_dir() / "calibration/ardrone2_front.json"));
}

}  // namespace
}  // namespace gs
