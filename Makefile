# hydrolux: the two commands a new user runs are `make demo` and `make test`.
# Both install missing Debian packages first (scripts/install-deps), then build Release into build/.

BUILD_DIR ?= build
BUILD_TYPE ?= Release
JOBS ?= $(shell nproc 2>/dev/null || echo 2)
GALLERY_DIR ?= out/gallery
# Warnings are errors in CI (CI=true), plain warnings elsewhere.
WERROR ?= $(if $(CI),ON,OFF)

# The sanitizer build (clang, AddressSanitizer + UndefinedBehaviorSanitizer, libFuzzer coverage):
# one build folder serves make test-sanitize and the fuzz targets (cmake/Sanitize.cmake).
SAN_DIR ?= build-sanitize
SAN_CC ?= clang-16
SAN_CXX ?= clang++-16
FUZZ_SECONDS ?= 300
FUZZ_SMOKE_SECONDS ?= 5
# Any sanitizer report fails the run; leaks too (fuzz/lsan.supp: known leaks in system libraries).
SAN_ENV = ASAN_OPTIONS=detect_leaks=1:strict_string_checks=1:detect_stack_use_after_return=1 \
          LSAN_OPTIONS=suppressions=$(CURDIR)/fuzz/lsan.supp \
          UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
          $(if $(wildcard /usr/bin/llvm-symbolizer),ASAN_SYMBOLIZER_PATH=/usr/bin/llvm-symbolizer)

.PHONY: all build deps configure web demo test bench clean install-python sanitize-build fuzz-build fuzz-smoke test-sanitize fuzz reference docs

all: build

deps:
	@scripts/install-deps

$(BUILD_DIR)/build.ninja:
	cmake -S . -B $(BUILD_DIR) -G Ninja -DCMAKE_BUILD_TYPE=$(BUILD_TYPE) -DHYDROLUX_WERROR=$(WERROR)

configure: $(BUILD_DIR)/build.ninja

build: configure
	cmake --build $(BUILD_DIR) -j $(JOBS)

# The web demo's npm packages (three, vite, playwright-core) from web/package-lock.json: npm ci runs
# again only when web/package.json or the lock file is newer than the last install.
WEB_STAMP := web/node_modules/.hydrolux-installed
$(WEB_STAMP): web/package.json web/package-lock.json
	@node -e 'const [a] = process.versions.node.split(".").map(Number); if (a < 18) { console.error("web: node " + process.versions.node + " is too old for Vite 6 (needs 18+)"); process.exit(1); }'
	cd web && npm ci --no-audit --no-fund
	@touch $@

web: deps
	@$(MAKE) --no-print-directory $(WEB_STAMP)

# docs/reference.md anew from the declared parameters and the CLI's flags (the test cli.test_reference
# fails while the file in the repository is not current).
reference: build
	HYDROLUX_WRITE_REFERENCE=1 $(BUILD_DIR)/bin/test_reference

# The documentation site into $(DOCS_DIR)/html (open index.html there): Sphinx (docs/conf.py) with
# warnings as errors, over the user guide (docs/*.md), the command reference, the parameter tables and
# the Python API generated from the build, and the gallery, rendered into $(DOCS_DIR)/gallery again
# whenever the CLI or its image plugin changed; every page is read afresh (-E: a warning is never hidden
# by the cache). ctest's docs.sphinx builds the same site.
DOCS_DIR ?= $(BUILD_DIR)/docs
DOCS_PYTHON ?= /usr/bin/python3
$(DOCS_DIR)/gallery/index.html: $(BUILD_DIR)/bin/hydrolux $(wildcard $(BUILD_DIR)/bin/libhydrolux_image_plugin.so)
	$(BUILD_DIR)/bin/hydrolux gallery -q -o $(DOCS_DIR)/gallery > /dev/null

docs: deps
	@$(MAKE) --no-print-directory build
	@$(MAKE) --no-print-directory $(DOCS_DIR)/gallery/index.html
	PYTHONPATH=$(abspath $(BUILD_DIR))/python HYDROLUX_DOCS_GALLERY=$(abspath $(DOCS_DIR))/gallery \
	  $(DOCS_PYTHON) -m sphinx -W --keep-going -E -q -b html -d $(DOCS_DIR)/doctrees docs $(DOCS_DIR)/html
	@echo "docs: $(DOCS_DIR)/html/index.html"

# The gallery, then the web demo's screenshot (headless chromium) into it as web_demo.png.
demo: deps
	@$(MAKE) --no-print-directory build
	@$(MAKE) --no-print-directory $(WEB_STAMP)
	$(BUILD_DIR)/bin/hydrolux gallery -o $(GALLERY_DIR)
	node tests/web/e2e.mjs --screenshot-only --hydrolux $(BUILD_DIR)/bin/hydrolux --web web \
	  --work $(BUILD_DIR)/web-demo --out $(GALLERY_DIR)

# Every test through ctest, then a short run of each fuzz target (FUZZ_SMOKE_SECONDS each).
test: deps
	@$(MAKE) --no-print-directory build
	@$(MAKE) --no-print-directory $(WEB_STAMP)
	cd $(BUILD_DIR) && ctest --output-on-failure -j $(JOBS)
	@$(MAKE) --no-print-directory fuzz-smoke

$(SAN_DIR)/build.ninja:
	CC=$(SAN_CC) CXX=$(SAN_CXX) cmake -S . -B $(SAN_DIR) -G Ninja -DCMAKE_BUILD_TYPE=Sanitize \
	  -DCMAKE_CXX_FLAGS_SANITIZE="-O1 -gline-tables-only" -DHYDROLUX_FUZZ=ON -DHYDROLUX_BUILD_BENCH=OFF -DHYDROLUX_BUILD_PYTHON=OFF \
	  -DHYDROLUX_FUZZ_SMOKE_SECONDS=$(FUZZ_SMOKE_SECONDS)

fuzz-build: $(SAN_DIR)/build.ninja
	cmake --build $(SAN_DIR) -j $(JOBS) --target fuzzers

fuzz-smoke: fuzz-build
	cd $(SAN_DIR) && $(SAN_ENV) ctest --output-on-failure -j $(JOBS) -L fuzz

sanitize-build: $(SAN_DIR)/build.ninja
	cmake --build $(SAN_DIR) -j $(JOBS)

# The test suite under AddressSanitizer and UndefinedBehaviorSanitizer (the CLI it drives too), but for
# the web demo's browser test (the Release suite runs it; its CLI runs, export and sky, are run under the
# sanitizers by tests/cli) and the whole gallery's render (the Release suite runs it; each figure's
# physics and renderer have their own tests here), and with the robustness test's documented subset
# (tests/cli/test_robustness.cpp).
test-sanitize: deps
	@$(MAKE) --no-print-directory sanitize-build
	cd $(SAN_DIR) && $(SAN_ENV) ctest --output-on-failure -j $(JOBS) -LE "fuzz|web|gallery"

# Each fuzz target (or those named in FUZZ_TARGETS, e.g. FUZZ_TARGETS=fuzz_image) for FUZZ_SECONDS
# on a scratch copy of its seed corpus; findings go to $(SAN_DIR)/fuzz-runs/<target>/findings/.
fuzz: deps
	@$(MAKE) --no-print-directory fuzz-build
	@mkdir -p $(SAN_DIR)/fuzz-runs; for b in $(if $(FUZZ_TARGETS),$(addprefix $(SAN_DIR)/bin/,$(FUZZ_TARGETS)),$(SAN_DIR)/bin/fuzz_*); do \
	  n=$$(basename $$b); echo "== $$n for $(FUZZ_SECONDS) s"; \
	  if $(SAN_ENV) fuzz/run_fuzzer.sh $$b fuzz/corpus/$${n#fuzz_} $(FUZZ_SECONDS) $(SAN_DIR)/fuzz-runs \
	       > $(SAN_DIR)/fuzz-runs/$$n.log 2>&1; then tail -n 4 $(SAN_DIR)/fuzz-runs/$$n.log; \
	  else tail -n 40 $(SAN_DIR)/fuzz-runs/$$n.log; echo "$$n: FINDING (see $(SAN_DIR)/fuzz-runs/$$n)"; exit 1; fi; \
	done

# The Python package into a virtual environment (made with /usr/bin/python3 -m venv --system-site-packages):
# pip's route (pyproject.toml, setup.py), taking the modules and the CLI from this build folder.
install-python: build
	@test -n "$(VENV)" || { echo "make install-python VENV=path/to/venv" >&2; exit 2; }
	@test -x "$(VENV)/bin/pip" || { echo "install-python: $(VENV) has no bin/pip (make it with /usr/bin/python3 -m venv --system-site-packages $(VENV))" >&2; exit 2; }
	HYDROLUX_BUILD_DIR=$(abspath $(BUILD_DIR)) $(VENV)/bin/pip install --no-build-isolation --no-index .

bench: deps
	@$(MAKE) --no-print-directory build
	@for b in $(BUILD_DIR)/bin/bench_*; do echo "== $$b"; $$b; done

clean:
	rm -rf $(BUILD_DIR) $(SAN_DIR)
