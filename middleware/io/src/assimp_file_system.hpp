// Assimp's file access through an engine's FileReader (ImportOptions::readFile): the model
// and every file it names (an OBJ's .mtl, an MD5 mesh's animation, ...) come from the
// reader, kept inside the model's folder unless ImportOptions::allowFilesOutsideModelFolder.
#pragma once
#include <assimp/IOSystem.hpp>

#include <filesystem>
#include <string>
#include <vector>

#include "marionette/core/file_reader.hpp"

namespace marionette::assimp_detail {

class ReaderFileSystem final : public Assimp::IOSystem {
 public:
  ReaderFileSystem(const FileReader& reader, const std::string& modelPath, bool allowOutside);
  bool Exists(const char* file) const override;
  char getOsSeparator() const override { return '/'; }
  Assimp::IOStream* Open(const char* file, const char* mode = "rb") override;
  void Close(Assimp::IOStream* stream) override;

  // Files refused or unreadable, one line each, for the import's diagnostics.
  [[nodiscard]] const std::vector<std::string>& problems() const noexcept { return problems_; }

 private:
  [[nodiscard]] bool permits(const std::string& file) const;
  const FileReader& reader_;
  std::filesystem::path root_;  // the model's folder, lexically normal
  bool allowOutside_ = false;
  mutable std::vector<std::string> problems_;
  // Assimp asks whether a file exists, then opens it: the bytes read to answer are kept for
  // the open that follows (one read of the engine's file, not two).
  mutable std::string checkedPath_, checkedBytes_;
};

}  // namespace marionette::assimp_detail
