// Atomic file writes (cullproof/io/files.hpp).
#include "cullproof/io/files.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <random>
#include <stdexcept>
#include <system_error>

namespace cullproof {

namespace {

// Writes all of `text` to `fd`; false (errno set) when the system refuses some of it.
bool write_all(int fd, std::string_view text) {
  std::size_t done = 0;
  while (done < text.size()) {
    const ssize_t n = ::write(fd, text.data() + done, text.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      if (n == 0) errno = EIO;
      return false;
    }
    done += static_cast<std::size_t>(n);
  }
  return true;
}

[[noreturn]] void cannot_write(const std::filesystem::path& file, const std::string& why) {
  throw std::runtime_error(file.string() + ": cannot write: " + why);
}

}  // namespace

void write_file_atomic(const std::filesystem::path& file, std::string_view text, bool overwrite) {
  namespace fs = std::filesystem;
  const fs::path dir = file.has_parent_path() ? file.parent_path() : fs::path(".");
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) cannot_write(file, "cannot create its directory " + dir.string() + ": " + ec.message());
  struct stat st{};
  if (::stat(file.c_str(), &st) == 0) {
    if (!overwrite) throw std::runtime_error(file.string() + ": exists already; not overwritten");
    if (!S_ISREG(st.st_mode)) {
      // A device or a pipe (/dev/stdout): renaming over it would replace it, so it is written as
      // it is; there is no partial file to leave behind.
      const int fd = ::open(file.c_str(), O_WRONLY | O_CLOEXEC);
      if (fd < 0) cannot_write(file, std::strerror(errno));
      const bool ok = write_all(fd, text);
      const int err = errno;
      if (::close(fd) != 0 && ok) cannot_write(file, std::strerror(errno));
      if (!ok) cannot_write(file, std::strerror(err));
      return;
    }
  }
  // A unique temporary name in the same directory, so rename() is atomic on POSIX. Hidden and not
  // ending in ".json": should the process die before the rename, no reader takes it for a case.
  std::random_device rd;
  const fs::path tmp = dir / ("." + file.filename().string() + ".tmp-" + std::to_string(::getpid()) +
                              "-" + std::to_string(rd()));
  const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0644);
  if (fd < 0) cannot_write(file, std::string(std::strerror(errno)) + " (creating " + tmp.filename().string() + " in " + dir.string() + ")");
  // From here every failure removes the temporary file: nothing half-written is left behind.
  auto fail = [&](const std::string& why) {
    ::unlink(tmp.c_str());
    cannot_write(file, why + "; nothing was written");
  };
  if (!write_all(fd, text)) {
    const std::string err = std::strerror(errno);
    ::close(fd);
    fail(err);
  }
  if (::fsync(fd) != 0) {
    const std::string err = std::strerror(errno);
    ::close(fd);
    fail(err);
  }
  if (::close(fd) != 0) fail(std::strerror(errno));
  if (!overwrite) {
    // link() fails if the target exists: no window in which another writer's file is replaced.
    if (::link(tmp.c_str(), file.c_str()) != 0) {
      if (errno == EEXIST) {
        ::unlink(tmp.c_str());
        throw std::runtime_error(file.string() + ": exists already; not overwritten");
      }
      fail(std::strerror(errno));
    }
    ::unlink(tmp.c_str());
  } else if (::rename(tmp.c_str(), file.c_str()) != 0) {
    fail(std::strerror(errno));
  }
  // The new name is durable once its directory is flushed too.
  const int dfd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (dfd >= 0) {
    const bool synced = ::fsync(dfd) == 0;
    const int err = errno;
    ::close(dfd);
    if (!synced && err != EINVAL)
      throw std::runtime_error(file.string() + ": written, but its directory could not be flushed: " + std::strerror(err));
  }
}

}  // namespace cullproof
