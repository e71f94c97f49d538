#include "shipped_data.hpp"

#include <string>

namespace marionette::capi {

FileReader shippedFileReader() {
  return [](const std::string& path, std::string& bytes, std::string& why) {
    for (std::size_t i = 0; i < kShippedFileCount; ++i)
      if (kShippedFiles[i].path == path) {
        bytes.assign(kShippedFiles[i].text);
        return true;
      }
    why = "not one of the built-in profiles and joint maps";
    return false;
  };
}

}  // namespace marionette::capi
