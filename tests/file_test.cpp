// dng::File: mapping real files, reporting I/O failures, ownership.
#include "dng/body.h"
#include "dng/file.h"
#include "sample_files.h"

#include "temp_dir.h"

#include <gtest/gtest.h>

#include <sys/stat.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <utility>
#include <vector>

namespace dng {
namespace {

namespace fs = std::filesystem;

class FileTest : public ::testing::Test {
protected:
  std::string path(const char* name) const { return (dir_ / name).string(); }
  testing::TempDir temp_{"file_test"};
  const fs::path& dir_ = temp_.path();
};

TEST_F(FileTest, MappedFileAnswersLikeTheBytesItHolds) {
  const auto bytes = testing::smallBrickedBox();
  testing::writeFileBytes(path("box.dng"), bytes);
  File file;
  Diagnostic diag;
  ASSERT_EQ(File::open(path("box.dng").c_str(), &file, &diag), Status::kOk) << diag.message;
  View in_memory;
  ASSERT_EQ(View::open(bytes.data(), bytes.size(), &in_memory), Status::kOk);
  EXPECT_EQ(file.view().sizeBytes(), bytes.size());
  EXPECT_EQ(file.view().verifyHashes(), Status::kOk);
  for (float x = -12.0f; x < 12.0f; x += 0.37f) {
    const Sample a = file.view().sample({x, 6.2f, 0.5f});
    const Sample b = in_memory.sample({x, 6.2f, 0.5f});
    ASSERT_EQ(a.status, b.status);
    ASSERT_EQ(a.distance, b.distance);
  }
}

TEST_F(FileTest, MoveTransfersOwnership) {
  testing::writeFileBytes(path("plane.dng"), testing::smallDensePlane());
  File a;
  ASSERT_EQ(File::open(path("plane.dng").c_str(), &a), Status::kOk);
  File b(std::move(a));
  EXPECT_FALSE(a.valid());
  ASSERT_TRUE(b.valid());
  File c;
  c = std::move(b);
  EXPECT_FALSE(b.valid());
  EXPECT_EQ(c.view().sample({1.0f, 1.0f, 0.9f}).status, SampleStatus::kInBand);
}

TEST_F(FileTest, MissingEmptyDirectoryAndDamagedFiles) {
  File file;
  Diagnostic diag;
  EXPECT_EQ(File::open(path("absent.dng").c_str(), &file, &diag), Status::kIoError);
  EXPECT_NE(std::string(diag.message).find("absent.dng"), std::string::npos) << diag.message;
  testing::writeFileBytes(path("empty.dng"), {});
  EXPECT_EQ(File::open(path("empty.dng").c_str(), &file), Status::kTruncated);
  EXPECT_EQ(File::open(dir_.string().c_str(), &file), Status::kIoError);
  auto bytes = testing::smallDensePlane();
  bytes.resize(bytes.size() - 1);
  testing::writeFileBytes(path("short.dng"), bytes);
  EXPECT_EQ(File::open(path("short.dng").c_str(), &file, &diag), Status::kTruncated);
  EXPECT_STREQ(diag.rule, "V8"); // the rule as its own field, not parsed out of the message
  EXPECT_EQ(std::strstr(diag.message, "V8"), nullptr) << diag.message;
  EXPECT_FALSE(file.valid());
  EXPECT_EQ(File::open(path("empty.dng").c_str(), &file, &diag), Status::kTruncated);
  EXPECT_STREQ(diag.rule, "V3");
  EXPECT_EQ(File::open(path("absent.dng").c_str(), &file, &diag), Status::kIoError);
  EXPECT_STREQ(diag.rule, "") << "I/O failures break no file rule";
  EXPECT_EQ(File::open(nullptr, &file), Status::kInvalidArgument);
}

// A FIFO has no writer here: opening it must not wait for one (it had hung until killed).
TEST_F(FileTest, AFifoIsRefusedAtOnce) {
  ASSERT_EQ(::mkfifo(path("pipe.dng").c_str(), 0600), 0) << std::strerror(errno);
  File file;
  Diagnostic diag;
  EXPECT_EQ(File::open(path("pipe.dng").c_str(), &file, &diag), Status::kIoError);
  EXPECT_NE(std::string(diag.message).find("not a regular file"), std::string::npos) << diag.message;
  EXPECT_FALSE(file.valid());
}

// Bodies point at a File's View: growing a std::vector<File> moves every File, and the bodies made
// from them must keep answering (under ASan a dangling View is a use-after-free).
TEST_F(FileTest, BodiesKeepWorkingWhenTheirFilesMove) {
  testing::writeFileBytes(path("box.dng"), testing::smallBrickedBox());
  std::vector<File> files;
  std::vector<Body> bodies;
  std::vector<const View*> views;
  for (int n = 0; n < 40; ++n) { // reallocates the vector several times
    files.emplace_back();
    ASSERT_EQ(File::open(path("box.dng").c_str(), &files.back()), Status::kOk);
    Body body;
    ASSERT_EQ(Body::create(&files.back().view(), Material(), &body), Status::kOk);
    bodies.push_back(body);
    views.push_back(&files.back().view());
  }
  for (std::size_t n = 0; n < files.size(); ++n) {
    EXPECT_EQ(bodies[n].field(), &files[n].view()) << n;
    EXPECT_EQ(views[n], &files[n].view()) << n;
    EXPECT_EQ(bodies[n].field()->sample({6.0f, 0.0f, 0.0f}).status, SampleStatus::kInBand) << n;
  }
  File moved = std::move(files[3]);
  EXPECT_EQ(&moved.view(), views[3]);
  EXPECT_FALSE(files[3].valid());
  EXPECT_FALSE(files[3].view().valid()); // an empty File hands out an empty View, never a dangling one
}

TEST_F(FileTest, FailedOpenReleasesWhatTheFileHeldBefore) {
  testing::writeFileBytes(path("plane.dng"), testing::smallDensePlane());
  File file;
  ASSERT_EQ(File::open(path("plane.dng").c_str(), &file), Status::kOk);
  EXPECT_EQ(File::open(path("absent.dng").c_str(), &file), Status::kIoError);
  EXPECT_FALSE(file.valid());
}

} // namespace
} // namespace dng
