#pragma once
/// \file file_io.h
/// \brief The two rules every module follows with files: what is read must be a
/// regular file (opening a FIFO blocks, a device can be endless), and what is written
/// appears whole or not at all (a full disk must not leave a damaged file where a good
/// one was).

#include <filesystem>
#include <functional>
#include <memory>
#include <ostream>
#include <string_view>

namespace plantnbv {

/// \brief Throws unless `path` names a regular file that can be opened for reading.
/// \throws FileNotFoundError if it does not exist; IoError if it is a directory, a
/// FIFO, a socket or a device, or cannot be opened. Messages start with "path: ".
void requireRegularFile(const std::filesystem::path& path);

/// \brief A file written whole or not at all. The stream writes into a temporary file
/// beside `path` (".NAME.tmp.PID.N", which readers of a directory skip); commit()
/// checks every write, flushes, fsyncs and closes it, then renames it over `path`. On
/// any failure, and if commit() is never reached (an exception while writing), the
/// temporary file is removed and the previous file at `path`, if any, is left as it
/// was.
///
/// \code
/// AtomicFile file("summary.json");
/// file.stream() << text;
/// file.commit(); // IoError "cannot write 'summary.json': No space left on device"
/// \endcode
class AtomicFile {
public:
  /// \throws IoError naming `path` if the temporary file cannot be created.
  explicit AtomicFile(std::filesystem::path path);
  ~AtomicFile();
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;

  /// \brief Where the content goes (binary: nothing is translated).
  std::ostream& stream();
  /// \brief Writes what is buffered, fsyncs and closes the temporary file, but renames
  /// nothing yet: files that belong together (a list and its index) are all prepared
  /// before the first is committed, so that a full disk leaves every one as it was.
  /// \throws IoError naming `path` and the system's reason.
  void prepare();
  /// \brief Makes the content the file at `path` (prepare() first if not done).
  /// \throws IoError naming `path` and the system's reason.
  void commit();

private:
  class Buffer;
  std::filesystem::path path_, temporary_;
  std::unique_ptr<Buffer> buffer_;
  std::unique_ptr<std::ostream> stream_;
  bool prepared_ = false, committed_ = false;
};

/// \brief AtomicFile in one call: `write` fills the stream. \throws IoError as
/// AtomicFile, and what `write` throws (the previous file is then kept).
void writeFileAtomically(const std::filesystem::path& path,
                         const std::function<void(std::ostream&)>& write);

/// \brief The same for a text already made.
void writeFileAtomically(const std::filesystem::path& path, std::string_view content);

/// \brief True for the name of AtomicFile's temporary files (".NAME.tmp.*").
bool isAtomicFileTemporary(const std::filesystem::path& path);

} // namespace plantnbv
