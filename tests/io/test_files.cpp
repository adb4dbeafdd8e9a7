// The one safe path for files (io/files.hpp): inputs that are not regular files are refused without
// blocking; outputs are reserved up front, written whole through a temporary file, and renamed into
// place only when every step succeeded; a full disk, a file-size limit or a read-only folder fails
// cleanly, leaving the old file as it was and no temporary file; an output that is an input is
// refused; a cancelled run removes what it had pending.
#include <gtest/gtest.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <unistd.h>

#include <csignal>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "hydrolux/core/error.hpp"
#include "hydrolux/io/files.hpp"
#include "support/sandbox.hpp"

namespace hydrolux::io {
namespace {

namespace fs = std::filesystem;
using hydrolux::testing::run_in_child;

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

void spit(const fs::path& p, const std::string& text) { std::ofstream(p, std::ios::binary) << text; }

class Files : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("hydrolux_test_files_" + std::to_string(::getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override {
    std::error_code ec;
    fs::permissions(dir_, fs::perms::owner_all, fs::perm_options::add, ec);
    fs::remove_all(dir_, ec);
  }
  // Every name in the folder, hidden ones included, sorted.
  std::vector<std::string> names(const fs::path& d) const {
    std::vector<std::string> n;
    for (const auto& e : fs::directory_iterator(d)) n.push_back(e.path().filename().string());
    std::sort(n.begin(), n.end());
    return n;
  }
  fs::path dir_;
};

TEST_F(Files, WriteCreatesReplacesAndKeepsPermissions) {
  const fs::path f = dir_ / "a.txt";
  write_file(f, "first");
  EXPECT_EQ(slurp(f), "first");
  fs::permissions(f, fs::perms::owner_read | fs::perms::owner_write | fs::perms::group_read);
  write_file(f, "second, longer");
  EXPECT_EQ(slurp(f), "second, longer");
  EXPECT_EQ(fs::status(f).permissions() & fs::perms::all,
            fs::perms::owner_read | fs::perms::owner_write | fs::perms::group_read);
  EXPECT_EQ(names(dir_), std::vector<std::string>{"a.txt"});
  EXPECT_EQ(pending_output_count(), 0u);
}

// Chunked writes and an empty file.
TEST_F(Files, OutputFileInChunksAndEmpty) {
  {
    OutputFile out(dir_ / "chunks.bin");
    out.write("abc");
    out.write(std::string(100000, 'z'));
    EXPECT_EQ(pending_output_count(), 1u);
    EXPECT_FALSE(fs::exists(dir_ / "chunks.bin"));  // nothing at the target until commit
    out.commit();
    EXPECT_TRUE(out.committed());
  }
  EXPECT_EQ(fs::file_size(dir_ / "chunks.bin"), 100003u);
  write_file(dir_ / "empty", "");
  EXPECT_EQ(fs::file_size(dir_ / "empty"), 0u);
  EXPECT_EQ(pending_output_count(), 0u);
}

// Writes at offsets (a container going back to patch its header), and reads at offsets.
TEST_F(Files, WriteAtAndReadAt) {
  {
    OutputFile out(dir_ / "video.mp4");
    out.write_at(0, "XXXXhead");
    out.write_at(8, std::string(1000, 'b'));
    out.write_at(0, "size");  // patched in place
    out.commit();
  }
  const std::string bytes = slurp(dir_ / "video.mp4");
  EXPECT_EQ(bytes.size(), 1008u);
  EXPECT_EQ(bytes.substr(0, 8), "sizehead");
  const InputFile in(dir_ / "video.mp4", "--video");
  EXPECT_EQ(in.size(), 1008u);
  char buf[16];
  EXPECT_EQ(in.read_at(4, buf, 4), 4u);
  EXPECT_EQ(std::string(buf, 4), "head");
  EXPECT_EQ(in.read_at(1004, buf, 16), 4u);  // short at the end
  EXPECT_EQ(in.read_at(5000, buf, 16), 0u);  // past it
  // Only regular files: a folder is refused with its label.
  try {
    InputFile bad(dir_, "--video");
    FAIL();
  } catch (const IoError& e) {
    EXPECT_NE(std::string(e.what()).find("--video"), std::string::npos);
  }
  EXPECT_EQ(pending_output_count(), 0u);
}

// An output abandoned (an exception during the work) leaves the old file and nothing else.
TEST_F(Files, AbandonedOutputLeavesNothing) {
  spit(dir_ / "keep.png", "old");
  {
    OutputFile out(dir_ / "keep.png");
    out.write("half of a new file");
  }  // destroyed without commit
  EXPECT_EQ(slurp(dir_ / "keep.png"), "old");
  EXPECT_EQ(names(dir_), std::vector<std::string>{"keep.png"});
  EXPECT_EQ(pending_output_count(), 0u);
}

// The folder is checked when the output is reserved, before any work: missing, not a folder.
// Messages name the path the caller gave (and its label), never a temporary name.
TEST_F(Files, FolderProblemsAreFoundAtReservation) {
  try {
    OutputFile out(dir_ / "missing" / "x.png", "-o");
    FAIL() << "a missing folder was accepted";
  } catch (const IoError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("-o " + (dir_ / "missing" / "x.png").string()), std::string::npos) << m;
    EXPECT_NE(m.find("does not exist"), std::string::npos) << m;
    EXPECT_EQ(m.find(".tmp-"), std::string::npos) << m;
  }
  spit(dir_ / "plain", "x");
  EXPECT_THROW(OutputFile(dir_ / "plain" / "x.png"), IoError);  // a file used as a folder
  fs::create_directories(dir_ / "adir");
  try {
    OutputFile out(dir_ / "adir");
    FAIL();
  } catch (const IoError& e) {
    EXPECT_NE(std::string(e.what()).find("is a folder"), std::string::npos) << e.what();
  }
  EXPECT_THROW(OutputFile(""), IoError);
}

// A device or a FIFO at the output's path is never replaced (renaming over /dev/null as root would
// replace the device node).
TEST_F(Files, SpecialFilesAreNeverReplaced) {
  try {
    OutputFile out("/dev/null");
    FAIL();
  } catch (const IoError& e) {
    EXPECT_NE(std::string(e.what()).find("character device"), std::string::npos) << e.what();
  }
  struct stat st {};
  ASSERT_EQ(::stat("/dev/null", &st), 0);
  EXPECT_TRUE(S_ISCHR(st.st_mode));
  ASSERT_EQ(::mkfifo((dir_ / "fifo").c_str(), 0600), 0);
  EXPECT_THROW(OutputFile(dir_ / "fifo"), IoError);
}

// A folder that exists but takes no new file: a read-only mount (which stops root too) and, for a
// non-root user, a folder without write permission. Refused at reservation, naming the folder and
// the OS's reason.
TEST_F(Files, UnwritableFolderIsFoundAtReservation) {
  const std::string ro = (dir_ / "ro").string();
  fs::create_directories(ro);
  const int code = run_in_child([&] {
    if (!testing::enter_private_mounts() || !testing::mount_tmpfs(ro, 64, /*read_only=*/true))
      return testing::kChildCannotSetUp;
    try {
      OutputDirectory existing(ro, "--out");  // an existing folder of outputs: probed at once too
      return 3;
    } catch (const IoError&) {
    }
    try {
      OutputFile out(ro + "/x.png", "-o");
      return 1;
    } catch (const IoError& e) {
      const std::string m = e.what();
      return m.find("cannot create a file in the folder") != std::string::npos &&
                     m.find("Read-only file system") != std::string::npos
                 ? 0
                 : 2;
    }
  });
  if (code == testing::kChildCannotSetUp) GTEST_SKIP() << "no private mount namespace here";
  EXPECT_EQ(code, 0);
  if (::geteuid() != 0) {
    fs::permissions(dir_ / "ro", fs::perms::owner_read | fs::perms::owner_exec);
    EXPECT_THROW(OutputFile(dir_ / "ro" / "x.png"), IoError);
  }
}

// A file-size limit (RLIMIT_FSIZE, with SIGXFSZ ignored as the CLI does) makes the write fail with
// EFBIG partway: IoFailure naming the path and the OS error, the old file untouched, no temporary
// file left.
TEST_F(Files, FileSizeLimitFailsCleanly) {
  const fs::path f = dir_ / "keep.exr";
  spit(f, "the old, good file");
  const int code = run_in_child([&] {
    std::signal(SIGXFSZ, SIG_IGN);
    const rlimit lim{4096, 4096};
    if (::setrlimit(RLIMIT_FSIZE, &lim) != 0) return testing::kChildCannotSetUp;
    try {
      write_file(f, std::string(100000, 'n'), "-o");
      return 1;
    } catch (const IoFailure& e) {
      const std::string m = e.what();
      return m.find(f.string()) != std::string::npos && m.find("File too large") != std::string::npos &&
                     m.find("is unchanged") != std::string::npos && m.find('\n') == std::string::npos
                 ? 0
                 : 2;
    }
  });
  ASSERT_NE(code, testing::kChildCannotSetUp);
  EXPECT_EQ(code, 0);
  EXPECT_EQ(slurp(f), "the old, good file");
  EXPECT_EQ(names(dir_), std::vector<std::string>{"keep.exr"});
}

// A real full disk: a 64 KiB tmpfs, filled up, then a write of more than is left: IoFailure with
// ENOSPC, the old file intact, no temporary file. Also for a folder of outputs.
TEST_F(Files, FullDiskFailsCleanly) {
  const std::string mnt = (dir_ / "mnt").string();
  fs::create_directories(mnt);
  const int code = run_in_child([&] {
    if (!testing::enter_private_mounts() || !testing::mount_tmpfs(mnt, 64)) return testing::kChildCannotSetUp;
    spit(mnt + "/keep.png", "old");
    testing::fill_up(mnt);
    const auto before = [&] {
      std::vector<std::string> n;
      for (const auto& e : fs::directory_iterator(mnt)) n.push_back(e.path().filename().string());
      std::sort(n.begin(), n.end());
      return n;
    };
    const auto listing = before();
    try {
      write_file(mnt + "/keep.png", std::string(200000, 'n'));
      return 1;
    } catch (const IoFailure& e) {
      if (std::string(e.what()).find("No space left on device") == std::string::npos) return 2;
    }
    if (slurp(mnt + "/keep.png") != "old" || before() != listing) return 3;
    try {
      OutputDirectory out(mnt + "/gallery");
      out.write("a.svg", std::string(200000, 'g'));
      return 4;
    } catch (const IoFailure& e) {
      if (std::string(e.what()).find("No space left on device") == std::string::npos) return 5;
    }
    if (before() != listing) return 6;  // the staging folder is gone
    return pending_output_count() == 0 ? 0 : 7;
  });
  if (code == testing::kChildCannotSetUp) GTEST_SKIP() << "no private mount namespace here";
  EXPECT_EQ(code, 0);
}

// A symbolic link is followed: the file it points to is replaced, the link kept.
TEST_F(Files, SymbolicLinkTargetIsReplaced) {
  spit(dir_ / "real.txt", "old");
  fs::create_symlink("real.txt", dir_ / "link.txt");
  write_file(dir_ / "link.txt", "new");
  EXPECT_TRUE(fs::is_symlink(dir_ / "link.txt"));
  EXPECT_EQ(slurp(dir_ / "real.txt"), "new");
  // A dangling link is refused, and left as it was.
  fs::create_symlink("nowhere/missing.txt", dir_ / "dangling.txt");
  EXPECT_THROW(write_file(dir_ / "dangling.txt", "new"), IoError);
  EXPECT_TRUE(fs::is_symlink(dir_ / "dangling.txt"));
}

// Inputs: a regular file is read whole; anything else is refused from its stat(), so a FIFO with no
// writer or /dev/zero cannot make the read block or run forever.
TEST_F(Files, InputsMustBeRegularFiles) {
  spit(dir_ / "in.bin", "12345");
  EXPECT_EQ(check_input_file(dir_ / "in.bin"), 5u);
  EXPECT_EQ(read_file(dir_ / "in.bin"), "12345");
  const auto message = [](const auto& call) {
    try {
      call();
    } catch (const IoError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  ASSERT_EQ(::mkfifo((dir_ / "fifo.png").c_str(), 0600), 0);
  EXPECT_NE(message([&] { (void)read_file(dir_ / "fifo.png", kMaxInputBytes, "--image"); })
                .find("--image " + (dir_ / "fifo.png").string() + ": a named pipe (FIFO), not a regular file"),
            std::string::npos);
  EXPECT_NE(message([] { (void)read_file("/dev/zero"); }).find("a character device"), std::string::npos);
  EXPECT_NE(message([&] { (void)read_file(dir_); }).find("a folder"), std::string::npos);
  EXPECT_NE(message([&] { (void)read_file(dir_ / "missing.png"); }).find("no such file"), std::string::npos);
  EXPECT_NE(message([&] { (void)read_file(dir_ / "in.bin", 4); }).find("more than the limit of 4 bytes"),
            std::string::npos);
  EXPECT_NE(message([] { (void)read_file(""); }).find("no file name"), std::string::npos);
}

TEST_F(Files, SameFileThroughLinksAndDots) {
  spit(dir_ / "a.png", "x");
  fs::create_symlink(dir_ / "a.png", dir_ / "soft.png");
  fs::create_hard_link(dir_ / "a.png", dir_ / "hard.png");
  fs::create_directories(dir_ / "sub");
  EXPECT_TRUE(same_file(dir_ / "a.png", dir_ / "a.png"));
  EXPECT_TRUE(same_file(dir_ / "a.png", dir_ / "soft.png"));
  EXPECT_TRUE(same_file(dir_ / "a.png", dir_ / "hard.png"));
  EXPECT_TRUE(same_file(dir_ / "a.png", dir_ / "sub" / ".." / "." / "a.png"));
  EXPECT_FALSE(same_file(dir_ / "a.png", dir_ / "b.png"));
  EXPECT_TRUE(same_file(dir_ / "new.png", dir_ / "sub" / ".." / "new.png"));  // neither exists yet
}

// The files of one run: an output equal to an input, by any name, is refused before anything is
// written; two outputs at one path too.
TEST_F(Files, FileSetRefusesOutputsThatAreInputs) {
  spit(dir_ / "in.png", "input");
  fs::create_symlink(dir_ / "in.png", dir_ / "alias.png");
  fs::create_hard_link(dir_ / "in.png", dir_ / "hard.png");
  for (const fs::path& out : {dir_ / "in.png", dir_ / "alias.png", dir_ / "hard.png", dir_ / "sub" / ".." / "in.png"}) {
    fs::create_directories(dir_ / "sub");
    FileSet files;
    files.input("--image", dir_ / "in.png");
    try {
      files.output("-o", out);
      ADD_FAILURE() << out;
    } catch (const IoError& e) {
      const std::string m = e.what();
      EXPECT_NE(m.find("-o " + out.string() + ": is the same file as the input --image"), std::string::npos) << m;
    }
  }
  {
    FileSet files;  // declared in the other order
    files.output("-o", dir_ / "in.png");
    EXPECT_THROW(files.input("--image", dir_ / "hard.png"), IoError);
  }
  {
    FileSet files;
    files.output("-o", dir_ / "out.png");
    EXPECT_THROW(files.output("--mask-out", dir_ / "out.png"), IoError);
  }
  EXPECT_EQ(slurp(dir_ / "in.png"), "input");
  FileSet ok;
  ok.input("--image", dir_ / "in.png");
  ok.output("-o", dir_ / "out.png").write("result");
  ok.commit();
  EXPECT_EQ(slurp(dir_ / "out.png"), "result");
}

// A folder of outputs: staged beside the destination, moved into place whole when new; into an
// existing folder, each file replaces its namesake and other files stay. Abandoned: nothing
// changes. An input inside the destination is never replaced.
TEST_F(Files, OutputDirectoryStagesAndCommits) {
  {
    OutputDirectory out(dir_ / "deep" / "gallery");
    out.write("a.svg", "A1");
    out.write("index.html", "I1");
    EXPECT_FALSE(fs::exists(dir_ / "deep" / "gallery"));
    EXPECT_EQ(names(dir_ / "deep").size(), 1u);  // the hidden staging folder
    out.commit();
  }
  EXPECT_EQ(names(dir_ / "deep"), std::vector<std::string>{"gallery"});
  EXPECT_EQ(slurp(dir_ / "deep" / "gallery" / "a.svg"), "A1");
  spit(dir_ / "deep" / "gallery" / "user-notes.txt", "mine");
  {
    OutputDirectory out(dir_ / "deep" / "gallery");
    out.write("a.svg", "A2");
  }  // abandoned
  EXPECT_EQ(slurp(dir_ / "deep" / "gallery" / "a.svg"), "A1");
  EXPECT_EQ(names(dir_ / "deep"), std::vector<std::string>{"gallery"});
  {
    OutputDirectory out(dir_ / "deep" / "gallery");
    out.write("a.svg", "A2");
    out.write("index.html", "I2");
    out.commit();
  }
  EXPECT_EQ(slurp(dir_ / "deep" / "gallery" / "a.svg"), "A2");
  EXPECT_EQ(slurp(dir_ / "deep" / "gallery" / "user-notes.txt"), "mine");
  {
    OutputDirectory out(dir_ / "deep" / "gallery");
    out.protect({dir_ / "deep" / "gallery" / "user-notes.txt"});
    out.write("user-notes.txt", "overwritten");
    EXPECT_THROW(out.commit(), IoError);
  }
  EXPECT_EQ(slurp(dir_ / "deep" / "gallery" / "user-notes.txt"), "mine");
  {
    // Into an existing folder the staging folder is made inside it (same file system, writability
    // proven at once), and a folder where a file would go is refused before anything moves.
    OutputDirectory out(dir_ / "deep" / "gallery");
    EXPECT_EQ(names(dir_ / "deep"), std::vector<std::string>{"gallery"});
    EXPECT_EQ(names(dir_ / "deep" / "gallery").size(), 4u);  // a.svg, index.html, user-notes.txt, staging
    fs::create_directories(dir_ / "deep" / "gallery" / "index.html.d");
    out.write("a.svg", "A3");
    out.write("index.html.d", "a file where a folder is");
    EXPECT_THROW(out.commit(), IoError);
  }
  EXPECT_EQ(slurp(dir_ / "deep" / "gallery" / "a.svg"), "A2");
  EXPECT_TRUE(fs::is_directory(dir_ / "deep" / "gallery" / "index.html.d"));
  EXPECT_EQ(names(dir_ / "deep" / "gallery").size(), 4u);  // the staging folder is gone
  {
    // One level of subfolders: new, then into an existing folder (other files kept); a subfolder
    // name that is a file in the destination is refused before anything moves; nested or
    // climbing names are refused.
    OutputDirectory out(dir_ / "assets");
    out.write("glsl/sky.glsl", "S1");
    out.write("top.json", "T1");
    EXPECT_THROW(out.write("a/b/c", "x"), IoError);
    EXPECT_THROW(out.write("../escape", "x"), IoError);
    EXPECT_THROW(out.write("glsl/", "x"), IoError);
    out.commit();
  }
  EXPECT_EQ(slurp(dir_ / "assets" / "glsl" / "sky.glsl"), "S1");
  spit(dir_ / "assets" / "glsl" / "mine.glsl", "mine");
  {
    OutputDirectory out(dir_ / "assets");
    out.write("glsl/sky.glsl", "S2");
    out.write("hlsl/sky.hlsl", "H2");
    out.commit();
  }
  EXPECT_EQ(slurp(dir_ / "assets" / "glsl" / "sky.glsl"), "S2");
  EXPECT_EQ(slurp(dir_ / "assets" / "glsl" / "mine.glsl"), "mine");
  EXPECT_EQ(slurp(dir_ / "assets" / "hlsl" / "sky.hlsl"), "H2");
  EXPECT_EQ(names(dir_ / "assets").size(), 3u);  // glsl, hlsl, top.json: no staging left
  spit(dir_ / "assets" / "wgsl", "a file");
  {
    OutputDirectory out(dir_ / "assets");
    out.write("glsl/sky.glsl", "S3");
    out.write("wgsl/sky.wgsl", "W3");
    EXPECT_THROW(out.commit(), IoError);
  }
  EXPECT_EQ(slurp(dir_ / "assets" / "glsl" / "sky.glsl"), "S2");
  EXPECT_EQ(names(dir_ / "assets").size(), 4u);
  EXPECT_THROW(OutputDirectory(dir_ / "deep" / "gallery" / "a.svg"), IoError);  // a file
  fs::create_directory_symlink("nowhere", dir_ / "dangling-gallery");
  EXPECT_THROW(OutputDirectory(dir_ / "dangling-gallery"), IoError);  // found now, not at the end
  EXPECT_EQ(pending_output_count(), 0u);
}

// Cancellation (what the CLI's Ctrl-C handler calls): every pending temporary file and staging
// folder is removed, and a commit after it fails, leaving the old file. In a child, because it
// blocks commits for the rest of the process.
TEST_F(Files, CancelRemovesPendingOutputs) {
  spit(dir_ / "keep.exr", "old");
  const int code = run_in_child([&] {
    OutputFile file(dir_ / "keep.exr");
    file.write("new data");
    OutputDirectory folder(dir_ / "gallery");
    folder.write("a.svg", "x");
    if (pending_output_count() != 2) return 1;
    if (cancel_pending_outputs() != 2) return 2;
    if (pending_output_count() != 0) return 3;
    try {
      file.commit();
      return 4;
    } catch (const IoFailure&) {
    }
    try {
      folder.commit();
      return 5;
    } catch (const IoFailure&) {
    }
    return 0;
  });
  EXPECT_EQ(code, 0);
  EXPECT_EQ(slurp(dir_ / "keep.exr"), "old");
  EXPECT_EQ(names(dir_), std::vector<std::string>{"keep.exr"});
}

}  // namespace
}  // namespace hydrolux::io
