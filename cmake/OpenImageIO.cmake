# Debian 12's OpenImageIOConfig exports /usr/include/opencv4, which does not exist unless OpenCV's
# headers are installed, and CMake then refuses to generate. Drop non-existent include directories.
find_package(OpenImageIO 2.4 CONFIG REQUIRED)
get_target_property(_oiio_includes OpenImageIO::OpenImageIO INTERFACE_INCLUDE_DIRECTORIES)
set(_oiio_existing_includes "")
foreach(_dir IN LISTS _oiio_includes)
  if(EXISTS "${_dir}")
    list(APPEND _oiio_existing_includes "${_dir}")
  endif()
endforeach()
set_target_properties(OpenImageIO::OpenImageIO PROPERTIES
  INTERFACE_INCLUDE_DIRECTORIES "${_oiio_existing_includes}")
