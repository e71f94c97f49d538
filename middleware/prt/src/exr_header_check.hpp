// A check of an OpenEXR file's headers before OpenImageIO opens it.
#pragma once
#include <string>

namespace marionette::prt {

// OpenEXR (3.1) allocates each header attribute at the size the file declares before
// reading it, so a 200-byte file can ask for 2 GiB. Walks the headers (one, or a multi-part
// file's list ending with an empty one) as OpenEXR does and returns what is wrong when an
// attribute declares more bytes than the file has, or has a name OpenEXR would cut short
// (and so read the rest as the size), or a data window over limits::imageSizeProblem or
// tiles under 8 pixels a side (OpenEXR sizes its chunk table from them when it opens the
// file); "" for a sound header or a file that is no EXR.
[[nodiscard]] std::string exrHeaderProblem(const std::string& path);

}  // namespace marionette::prt
