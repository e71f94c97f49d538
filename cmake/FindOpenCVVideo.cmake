# FindOpenCVVideo: the parts of OpenCV the AR renderer's background sources use
# (core, imgproc, videoio). Debian's split packages libopencv-core-dev,
# libopencv-imgproc-dev and libopencv-videoio-dev ship no OpenCVConfig.cmake,
# so the headers and libraries are found directly.
#
# Defines OpenCVVideo_FOUND, OpenCVVideo_INCLUDE_DIR and the imported target
# OpenCVVideo::OpenCVVideo (all three libraries, headers in /usr/include/opencv4).
find_path(OpenCVVideo_INCLUDE_DIR opencv2/videoio.hpp PATH_SUFFIXES opencv4)
find_library(OpenCVVideo_core_LIBRARY opencv_core)
find_library(OpenCVVideo_imgproc_LIBRARY opencv_imgproc)
find_library(OpenCVVideo_videoio_LIBRARY opencv_videoio)

include(FindPackageHandleStandardArgs)
find_package_handle_standard_args(OpenCVVideo REQUIRED_VARS
  OpenCVVideo_INCLUDE_DIR OpenCVVideo_core_LIBRARY OpenCVVideo_imgproc_LIBRARY OpenCVVideo_videoio_LIBRARY)
mark_as_advanced(OpenCVVideo_INCLUDE_DIR OpenCVVideo_core_LIBRARY OpenCVVideo_imgproc_LIBRARY
                 OpenCVVideo_videoio_LIBRARY)

if(OpenCVVideo_FOUND AND NOT TARGET OpenCVVideo::OpenCVVideo)
  add_library(OpenCVVideo::OpenCVVideo INTERFACE IMPORTED)
  set_target_properties(OpenCVVideo::OpenCVVideo PROPERTIES
    INTERFACE_INCLUDE_DIRECTORIES "${OpenCVVideo_INCLUDE_DIR}"
    INTERFACE_LINK_LIBRARIES
      "${OpenCVVideo_videoio_LIBRARY};${OpenCVVideo_imgproc_LIBRARY};${OpenCVVideo_core_LIBRARY}")
endif()
