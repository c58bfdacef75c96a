#include "pheromesh/core/atomic_file.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <filesystem>
#include <system_error>
#include <utility>

namespace pheromesh::core {
namespace {

std::string errno_text(int err) { return std::error_code(err, std::generic_category()).message(); }

// The rename is durable only once the directory entry reaches the disk.
void sync_directory(const std::filesystem::path& dir) {
  const int fd = ::open(dir.empty() ? "." : dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd < 0) return;  // best effort: the file itself is complete either way
  (void)::fsync(fd);
  (void)::close(fd);
}

}  // namespace

std::string atomic_temp_path(const std::string& path) {
  const std::filesystem::path p(path);
  return (p.parent_path() / ("." + p.filename().string() + ".tmp-" + std::to_string(::getpid()))).string();
}

Result<AtomicFile> AtomicFile::create(const std::string& path) {
  const std::filesystem::path p(path);
  if (p.filename().empty()) return Error{"cannot write '" + path + "': not a file name"};
  if (!p.parent_path().empty()) {
    std::error_code ec;
    std::filesystem::create_directories(p.parent_path(), ec);
    if (ec) return Error{"cannot create directory " + p.parent_path().string() + ": " + ec.message()};
  }
  std::string temp = atomic_temp_path(path);
  std::FILE* f = std::fopen(temp.c_str(), "wbe");  // "e": O_CLOEXEC, so launched children do not inherit it
  if (f == nullptr) return Error{"cannot write " + path + " (as " + temp + "): " + errno_text(errno)};
  return AtomicFile(path, std::move(temp), f);
}

AtomicFile::AtomicFile(AtomicFile&& other) noexcept
    : path_(std::move(other.path_)), temp_(std::move(other.temp_)), file_(std::exchange(other.file_, nullptr)),
      error_(other.error_) {}

AtomicFile& AtomicFile::operator=(AtomicFile&& other) noexcept {
  if (this != &other) {
    discard();
    path_ = std::move(other.path_);
    temp_ = std::move(other.temp_);
    file_ = std::exchange(other.file_, nullptr);
    error_ = other.error_;
  }
  return *this;
}

AtomicFile::~AtomicFile() { discard(); }

void AtomicFile::discard() {
  if (file_ == nullptr) return;
  std::fclose(file_);
  file_ = nullptr;
  std::remove(temp_.c_str());
}

bool AtomicFile::write(std::string_view bytes) {
  if (file_ == nullptr) return false;
  if (bytes.empty()) return error_ == 0;
  if (std::fwrite(bytes.data(), 1, bytes.size(), file_) != bytes.size() && error_ == 0) error_ = errno != 0 ? errno : EIO;
  return error_ == 0;
}

bool AtomicFile::flush() {
  if (file_ == nullptr) return false;
  if (std::fflush(file_) != 0 && error_ == 0) error_ = errno != 0 ? errno : EIO;
  return error_ == 0;
}

Result<std::size_t> AtomicFile::commit() {
  if (file_ == nullptr) return Error{"cannot write " + path_ + ": already closed"};
  const auto fail = [this](const std::string& step, int err) {
    discard();
    return Error{"cannot write " + path_ + ": " + step + ": " + errno_text(err)};
  };
  if (std::ferror(file_) != 0 && error_ == 0) error_ = EIO;
  if (error_ != 0) return fail("write", error_);
  if (std::fflush(file_) != 0) return fail("flush", errno);
  const long size = std::ftell(file_);
  if (::fsync(::fileno(file_)) != 0) return fail("fsync", errno);
  std::FILE* f = std::exchange(file_, nullptr);
  if (std::fclose(f) != 0) {
    const int err = errno;
    std::remove(temp_.c_str());
    return Error{"cannot write " + path_ + ": close: " + errno_text(err)};
  }
  if (std::rename(temp_.c_str(), path_.c_str()) != 0) {
    const int err = errno;
    std::remove(temp_.c_str());
    return Error{"cannot write " + path_ + ": rename from " + temp_ + ": " + errno_text(err)};
  }
  sync_directory(std::filesystem::path(path_).parent_path());
  return static_cast<std::size_t>(size < 0 ? 0 : size);
}

Result<std::size_t> write_file_atomically(const std::string& path, std::string_view content) {
  auto f = AtomicFile::create(path);
  if (!f) return f.error();
  f->write(content);
  return f->commit();
}

}  // namespace pheromesh::core
