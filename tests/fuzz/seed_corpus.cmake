# cmake -DCORPUS=dir -DARTIFACTS=dir -DSEED_DIRS="a;b" -P seed_corpus.cmake
# Replaces CORPUS with a flat copy of every file in SEED_DIRS (names prefixed by their folder, so equal
# names cannot collide), so each short fuzz run starts from the seeds and the sources are never written
# to. Creates ARTIFACTS, where libFuzzer leaves the input of a crash.
file(REMOVE_RECURSE "${CORPUS}")
file(MAKE_DIRECTORY "${CORPUS}" "${ARTIFACTS}")
set(count 0)
foreach(dir IN LISTS SEED_DIRS)
  if(NOT IS_DIRECTORY "${dir}")
    continue()
  endif()
  get_filename_component(folder "${dir}" NAME)
  file(GLOB seeds LIST_DIRECTORIES false "${dir}/*")
  foreach(seed IN LISTS seeds)
    get_filename_component(name "${seed}" NAME)
    configure_file("${seed}" "${CORPUS}/${folder}_${name}" COPYONLY)
    math(EXPR count "${count} + 1")
  endforeach()
endforeach()
if(count EQUAL 0)
  message(FATAL_ERROR "no seed files found in ${SEED_DIRS}")
endif()
message(STATUS "${count} seeds copied to ${CORPUS}")
