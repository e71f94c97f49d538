#include "assimp_file_system.hpp"

#include <assimp/IOStream.hpp>

#include <algorithm>
#include <cstring>

#include "marionette/core/limits.hpp"
#include "model_folder.hpp"

namespace marionette::assimp_detail {
namespace {

// A whole file in memory, owned (Assimp's MemoryIOStream only borrows its buffer).
class OwnedStream final : public Assimp::IOStream {
 public:
  explicit OwnedStream(std::string bytes) : bytes_(std::move(bytes)) {}
  size_t Read(void* out, size_t size, size_t count) override {
    if (size == 0 || count == 0 || position_ >= bytes_.size()) return 0;
    const size_t items = std::min(count, (bytes_.size() - position_) / size);
    std::memcpy(out, bytes_.data() + position_, items * size);
    position_ += items * size;
    return items;
  }
  size_t Write(const void*, size_t, size_t) override { return 0; }  // read-only
  aiReturn Seek(size_t offset, aiOrigin origin) override {
    size_t target = 0;
    switch (origin) {
      case aiOrigin_SET: target = offset; break;
      case aiOrigin_CUR:
        if (offset > bytes_.size() - position_) return aiReturn_FAILURE;
        target = position_ + offset;
        break;
      case aiOrigin_END: target = bytes_.size() - offset; break;  // Assimp passes a distance back from the end
      default: return aiReturn_FAILURE;
    }
    if (target > bytes_.size()) return aiReturn_FAILURE;
    position_ = target;
    return aiReturn_SUCCESS;
  }
  size_t Tell() const override { return position_; }
  size_t FileSize() const override { return bytes_.size(); }
  void Flush() override {}

 private:
  std::string bytes_;
  size_t position_ = 0;
};

std::string normalized(const char* file) { return std::filesystem::path(file).lexically_normal().generic_string(); }

}  // namespace

ReaderFileSystem::ReaderFileSystem(const FileReader& reader, const std::string& modelPath, bool allowOutside)
    : reader_(reader), root_(std::filesystem::path(modelPath).parent_path().lexically_normal()),
      allowOutside_(allowOutside) {}

bool ReaderFileSystem::permits(const std::string& file) const {
  if (allowOutside_ || io_detail::insideFolder(file, root_)) return true;
  problems_.push_back("'" + file + "' is outside the model's folder '" + root_.generic_string() +
                      "': not read (ImportOptions::allowFilesOutsideModelFolder allows it)");
  return false;
}

bool ReaderFileSystem::Exists(const char* file) const {
  if (!file) return false;
  const std::string path = normalized(file);
  if (!permits(path)) return false;
  std::string why;
  if (path == checkedPath_) return true;
  if (!readWholeFile(reader_, path, limits::kMaxModelFileBytes, checkedBytes_, why)) return false;
  checkedPath_ = path;
  return true;
}

Assimp::IOStream* ReaderFileSystem::Open(const char* file, const char* mode) {
  if (!file || (mode && std::strchr(mode, 'w'))) return nullptr;  // Assimp only reads here
  const std::string path = normalized(file);
  if (!permits(path)) return nullptr;
  std::string bytes, why;
  if (path == checkedPath_) {  // read by Exists just before
    checkedPath_.clear();
    return new OwnedStream(std::move(checkedBytes_));
  }
  if (!readWholeFile(reader_, path, limits::kMaxModelFileBytes, bytes, why)) {
    problems_.push_back("the file reader could not read '" + path + "': " + why);
    return nullptr;
  }
  return new OwnedStream(std::move(bytes));
}

void ReaderFileSystem::Close(Assimp::IOStream* stream) { delete stream; }

}  // namespace marionette::assimp_detail
