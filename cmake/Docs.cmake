# The documentation site (docs/conf.py; make docs builds it into build/docs/html) as a ctest entry:
# Sphinx with warnings as errors (-W), every page read afresh (-E), into a scratch folder of the
# build tree, with the package built here on PYTHONPATH (autodoc and the parameter tables import
# it). A broken reference, a docstring that is not valid reST or a figure missing from the gallery
# fails it. The gallery page shows the gallery that gallery.test_gallery renders into the build tree
# (the fixture hydrolux_gallery, tests/CMakeLists.txt), so the suite renders the gallery once.
# Needs Debian's python3-sphinx and python3-myst-parser (scripts/install-deps).
set(HYDROLUX_DOCS_TEST_DIR ${CMAKE_BINARY_DIR}/docs-test)
add_test(NAME docs.sphinx
  COMMAND ${Python3_EXECUTABLE} -m sphinx -W --keep-going -E -q -b html
    -d ${HYDROLUX_DOCS_TEST_DIR}/doctrees ${PROJECT_SOURCE_DIR}/docs ${HYDROLUX_DOCS_TEST_DIR}/html)
set_tests_properties(docs.sphinx PROPERTIES LABELS docs
  FIXTURES_REQUIRED hydrolux_gallery
  ENVIRONMENT "PYTHONPATH=${CMAKE_BINARY_DIR}/python;HYDROLUX_DOCS_GALLERY=${CMAKE_BINARY_DIR}/tests/gallery-render;PYTHONDONTWRITEBYTECODE=1")
