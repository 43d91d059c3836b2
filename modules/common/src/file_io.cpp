#include <atomic>
#include <cerrno>
#include <cstring>
#include <fcntl.h>
#include <streambuf>
#include <string>
#include <sys/stat.h>
#include <unistd.h>
#include <vector>

#include <plantnbv/common/error.h>
#include <plantnbv/common/file_io.h>

namespace plantnbv {

namespace fs = std::filesystem;

namespace {

std::string quoted(const fs::path& path)
{
  return "'" + path.string() + "'";
}

/// The prefix of io's messages, "path: ".
std::string where(const fs::path& path)
{
  return path.string() + ": ";
}

std::string reason(int error)
{
  return error ? std::strerror(error) : "unknown error";
}

} // namespace

void requireRegularFile(const fs::path& path)
{
  struct stat st {};
  // stat, not lstat: a link to a regular file is one.
  if (::stat(path.c_str(), &st) != 0) {
    if (errno == ENOENT || errno == ENOTDIR)
      throw FileNotFoundError(where(path) + "no such file");
    throw IoError(where(path) + reason(errno));
  }
  if (S_ISDIR(st.st_mode))
    throw IoError(where(path) + "is a directory, expected a file");
  if (!S_ISREG(st.st_mode))
    throw IoError(where(path) + "is not a regular file (a FIFO, socket or device)");
  if (::access(path.c_str(), R_OK) != 0)
    throw IoError(where(path) + "cannot open for reading: " + reason(errno));
}

/// A stream buffer over a file descriptor that keeps the first write error (errno), so
/// that commit() can say why ("No space left on device", "File too large").
class AtomicFile::Buffer : public std::streambuf {
public:
  explicit Buffer(int fd) : fd_(fd), data_(1 << 16)
  {
    setp(data_.data(), data_.data() + data_.size());
  }
  ~Buffer() override
  {
    if (fd_ >= 0)
      ::close(fd_);
  }
  int error() const { return error_; }

  /// Writes what is buffered, fsyncs and closes; false (error() says why) on failure.
  bool finish()
  {
    if (!drain() || ::fsync(fd_) != 0)
      keep(errno);
    const int fd = fd_;
    fd_ = -1;
    if (::close(fd) != 0)
      keep(errno);
    return error_ == 0;
  }

protected:
  int_type overflow(int_type ch) override
  {
    if (!drain())
      return traits_type::eof();
    if (!traits_type::eq_int_type(ch, traits_type::eof())) {
      *pptr() = traits_type::to_char_type(ch);
      pbump(1);
    }
    return traits_type::not_eof(ch);
  }
  int sync() override { return drain() ? 0 : -1; }

private:
  void keep(int error)
  {
    if (error_ == 0)
      error_ = error ? error : EIO;
  }
  bool drain()
  {
    if (error_)
      return false;
    const char* p = pbase();
    while (p < pptr()) {
      const ssize_t n = ::write(fd_, p, static_cast<std::size_t>(pptr() - p));
      if (n < 0 && errno == EINTR)
        continue;
      if (n <= 0) {
        keep(n < 0 ? errno : ENOSPC);
        return false;
      }
      p += n;
    }
    setp(data_.data(), data_.data() + data_.size());
    return true;
  }

  int fd_;
  std::vector<char> data_;
  int error_ = 0;
};

AtomicFile::AtomicFile(fs::path path) : path_(std::move(path))
{
  static std::atomic<unsigned long> counter{0};
  const fs::path dir = path_.has_parent_path() ? path_.parent_path() : fs::path(".");
  if (path_.filename().empty())
    throw IoError("cannot write " + quoted(path_) + ": it names a directory");
  temporary_ = dir / ("." + path_.filename().string() + ".tmp." +
                      std::to_string(::getpid()) + "." + std::to_string(counter++));
  const int fd =
      ::open(temporary_.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
  if (fd < 0)
    throw IoError("cannot write " + quoted(path_) + ": " + reason(errno));
  buffer_ = std::make_unique<Buffer>(fd);
  stream_ = std::make_unique<std::ostream>(buffer_.get());
}

AtomicFile::~AtomicFile()
{
  if (!committed_) {
    stream_.reset();
    buffer_.reset(); // closes it
    ::unlink(temporary_.c_str());
  }
}

std::ostream& AtomicFile::stream()
{
  return *stream_;
}

void AtomicFile::prepare()
{
  if (prepared_)
    return;
  prepared_ = true;
  stream_->flush();
  if (!buffer_->finish() || !stream_->good()) {
    ::unlink(temporary_.c_str());
    committed_ = true; // nothing left to remove
    throw IoError("cannot write " + quoted(path_) + ": " +
                  reason(buffer_->error() ? buffer_->error() : EIO));
  }
}

void AtomicFile::commit()
{
  if (committed_)
    return;
  prepare();
  if (::rename(temporary_.c_str(), path_.c_str()) != 0) {
    const int error = errno;
    ::unlink(temporary_.c_str());
    committed_ = true;
    throw IoError("cannot write " + quoted(path_) + ": " + reason(error));
  }
  committed_ = true;
  // The rename itself reaches the disk with the directory.
  const fs::path dir = path_.has_parent_path() ? path_.parent_path() : fs::path(".");
  const int dir_fd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (dir_fd >= 0) {
    ::fsync(dir_fd);
    ::close(dir_fd);
  }
}

void writeFileAtomically(const fs::path& path,
                         const std::function<void(std::ostream&)>& write)
{
  AtomicFile file(path);
  write(file.stream());
  file.commit();
}

void writeFileAtomically(const fs::path& path, std::string_view content)
{
  AtomicFile file(path);
  file.stream().write(content.data(), static_cast<std::streamsize>(content.size()));
  file.commit();
}

bool isAtomicFileTemporary(const fs::path& path)
{
  const std::string name = path.filename().string();
  return name.size() > 1 && name[0] == '.' && name.find(".tmp.") != std::string::npos;
}

} // namespace plantnbv
