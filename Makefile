# hydrolux: the two commands a new user runs are `make demo` and `make test`.
# Both install missing Debian packages first (scripts/install-deps), then build Release into build/.

BUILD_DIR ?= build
BUILD_TYPE ?= Release
JOBS ?= $(shell nproc 2>/dev/null || echo 2)
GALLERY_DIR ?= out/gallery
# Warnings are errors in CI (CI=true), plain warnings elsewhere.
WERROR ?= $(if $(CI),ON,OFF)

.PHONY: all build deps configure demo test bench clean

all: build

deps:
	@scripts/install-deps

$(BUILD_DIR)/build.ninja:
	cmake -S . -B $(BUILD_DIR) -G Ninja -DCMAKE_BUILD_TYPE=$(BUILD_TYPE) -DHYDROLUX_WERROR=$(WERROR)

configure: $(BUILD_DIR)/build.ninja

build: configure
	cmake --build $(BUILD_DIR) -j $(JOBS)

demo: deps
	@$(MAKE) --no-print-directory build
	$(BUILD_DIR)/bin/hydrolux gallery -o $(GALLERY_DIR)

test: deps
	@$(MAKE) --no-print-directory build
	cd $(BUILD_DIR) && ctest --output-on-failure -j $(JOBS)

bench: deps
	@$(MAKE) --no-print-directory build
	@for b in $(BUILD_DIR)/bin/bench_*; do echo "== $$b"; $$b; done

clean:
	rm -rf $(BUILD_DIR)
