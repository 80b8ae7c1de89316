// write_files_atomically: all files appear, or none, and nothing temporary stays behind.

#include "cgamesh/io/atomic_file.hpp"

#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "cgamesh/errors.hpp"
#include "support/temp_dir.hpp"

namespace {

namespace fs = std::filesystem;
using cgamesh::io::OutputFile;
using cgamesh::io::write_file_atomically;
using cgamesh::io::write_files_atomically;
using cgamesh::WriteError;

using cgamesh_test::TempDir;

std::string read_text(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

TEST(AtomicFile, WritesAndReplaces) {
  TempDir dir;
  const std::string binary("a\0b\xff", 4);
  write_file_atomically(dir.path() / "x.bin", binary);
  EXPECT_EQ(read_text(dir.path() / "x.bin"), binary);
  write_file_atomically(dir.path() / "x.bin", "second");
  EXPECT_EQ(read_text(dir.path() / "x.bin"), "second");
  write_file_atomically(dir.path() / "empty", "");
  EXPECT_EQ(fs::file_size(dir.path() / "empty"), 0u);
  EXPECT_EQ(dir.entries(), (std::vector<std::string>{"empty", "x.bin"}));
}

TEST(AtomicFile, SeveralFilesAllAppear) {
  TempDir dir;
  fs::create_directory(dir.path() / "sub");
  const OutputFile files[] = {{dir.path() / "a", "A"}, {dir.path() / "sub" / "b", "B"}};
  write_files_atomically(files);
  EXPECT_EQ(read_text(dir.path() / "a"), "A");
  EXPECT_EQ(read_text(dir.path() / "sub" / "b"), "B");
  EXPECT_EQ(dir.entries(), (std::vector<std::string>{"a", "sub"}));
}

TEST(AtomicFile, FailedRenameRestoresEarlierTargets) {
  TempDir dir;
  { std::ofstream(dir.path() / "a") << "old a"; }
  fs::create_directory(dir.path() / "d");  // renaming a file onto a directory fails
  const OutputFile files[] = {{dir.path() / "a", "new a"}, {dir.path() / "fresh", "new"}, {dir.path() / "d", "x"}};
  EXPECT_THROW(write_files_atomically(files), WriteError);
  EXPECT_EQ(read_text(dir.path() / "a"), "old a");
  EXPECT_EQ(dir.entries(), (std::vector<std::string>{"a", "d"}));
  EXPECT_TRUE(fs::is_empty(dir.path() / "d"));
}

TEST(AtomicFile, MissingDirectoryWritesNothing) {
  TempDir dir;
  const OutputFile files[] = {{dir.path() / "a", "A"}, {dir.path() / "missing" / "b", "B"}};
  EXPECT_THROW(write_files_atomically(files), WriteError);
  EXPECT_TRUE(dir.entries().empty());
}

TEST(AtomicFile, RejectsDuplicateAndEmptyPaths) {
  TempDir dir;
  const OutputFile twice[] = {{dir.path() / "a", "1"}, {dir.path() / "." / "a", "2"}};
  EXPECT_THROW(write_files_atomically(twice), cgamesh::InvalidInputError);
  EXPECT_THROW(write_file_atomically("", "x"), cgamesh::InvalidInputError);
  EXPECT_THROW(write_file_atomically(dir.path() / "", "x"), cgamesh::InvalidInputError);
  EXPECT_TRUE(dir.entries().empty());
}

}  // namespace
