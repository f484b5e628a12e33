# patchwork: plain Makefile, no other build system needed.
#
#   make            build the CLI, examples, tests and benchmarks into build/
#   make demo       render every method on built-in data into out/
#   make test       build and run the whole test suite, JOBS at a time (ends with
#                   "N passed, N failed, N skipped")
#   make bench      benchmarks (medians of several runs), against peers where
#                   installed, ending with a summary table
#   make bench-report  the same, also written to bench/results.md
#   make data       extract real test data from installed Debian packages into data/
#   make js         npm packages of the browser checks (glTF validator, three.js,
#                   puppeteer-core) into tests/js/node_modules, versions pinned
#   make headers    regenerate the single-file headers from src/
#   make format     lay out src/, cli/ and examples/ with clang-format (.clang-format)
#   make fuzz       run each libFuzzer target for FUZZ_SECONDS (needs clang)
#   make fuzz-long  a campaign: each target for FUZZ_SECONDS (default 1800) on
#                   JOBS cores, the corpus kept and minimised in fuzz/work/,
#                   seeds that grow coverage merged into fuzz/corpus/
#                   (FUZZ_ONLY="fuzz_lst fuzz_mesh" for some only)
#   make clean
#
# CC and CFLAGS can be overridden; SANITIZE=1 builds with address and
# undefined-behaviour sanitizers (into build-san/, at -O1 with line tables
# only: -g1 keeps file:line in the reports at 60% of the compile time of -g).

CC       ?= cc
CXX      ?= c++
ifeq ($(SANITIZE),1)
CFLAGS   ?= -O1 -g1
else
CFLAGS   ?= -O2 -g
endif
WARN     := -std=c99 -Wall -Wextra -pedantic
LDLIBS   := -lm
FUZZ_CC  ?= clang
FUZZ_SECONDS ?= 60
# parallel builds and test runs (make test JOBS=1 for one at a time)
JOBS     ?= $(shell getconf _NPROCESSORS_ONLN 2>/dev/null || echo 1)

ifeq ($(SANITIZE),1)
BUILD    := build-san
SANFLAGS := -fsanitize=address,undefined -fno-sanitize-recover=all -fno-omit-frame-pointer
else
BUILD    := build
SANFLAGS :=
endif

ALL_CFLAGS = $(WARN) $(CFLAGS) $(SANFLAGS) -I.

# ---- single-file headers: name and the shared modules each one carries ----
HEADERS        := tiled lapped pgp lst
MODULES_tiled  := base vec rng noise image deflate:PW_NO_PNG png text mesh shapes halfedge subdiv sparse zsparse zamg trimesh heap dirfield periodic raster:PW_NO_RENDER parallel render graphcut quilt glue gltf
MODULES_lapped := base vec rng noise image deflate:PW_NO_PNG png text mesh shapes halfedge sparse raster parallel render polyhull trimesh heap atlas atlas_charts atlas_pack atlas_bake dirfield glue gltf
PARTS_lapped   := core field patch builtin grow render atlas io
PARTS_tiled    := core layout cells map synth validate builtin render io
MODULES_pgp    := base vec rng noise image deflate png text mesh shapes halfedge sparse zsparse zamg raster parallel render trimesh heap atlas atlas_charts atlas_pack atlas_bake dirfield periodic nrrd tile3 glue gltf graphcut quilt edt kdtree pca
PARTS_pgp      := core field solve edit render builtin io export morph synth
MODULES_lst    := base vec rng noise image deflate png text mesh shapes halfedge trimesh heap sparse raster parallel render atlas atlas_charts atlas_pack atlas_bake nrrd tetmesh tetio bisect stuffing edt pca glue gltf
PARTS_lst      := core exemplar field paste render cut builtin io export

COMMON_SRC := $(wildcard src/common/*.h src/*/*.h)
HEADER_FILES := $(addsuffix .h,$(HEADERS))

.PHONY: all demo test test-build bench bench-report bench-compile data headers check-headers print-headers format print-format-files dev-header fuzz fuzz-build fuzz-targets fuzz-long js clean

CLI_SRC   := $(wildcard cli/*.c)
TEST_SRC  := $(wildcard tests/test_*.c)
EX_SRC    := $(wildcard examples/*.c)
BENCH_SRC := $(wildcard bench/bench_*.c)
FUZZ_SRC  := $(wildcard fuzz/fuzz_*.c)

TEST_BIN  := $(patsubst tests/%.c,$(BUILD)/tests/%,$(TEST_SRC))
EX_BIN    := $(patsubst examples/%.c,$(BUILD)/examples/%,$(EX_SRC))
BENCH_BIN := $(patsubst bench/%.c,$(BUILD)/bench/%,$(BENCH_SRC))
BENCH_TOOLS := $(BUILD)/bench/sysdump $(BUILD)/bench/meshinfo

all: $(BUILD)/patchwork $(EX_BIN) $(TEST_BIN) $(BENCH_BIN) $(BENCH_TOOLS)

# The shell command that writes header $(1) to stdout.
gen_header = sh tools/amalgamate.sh $(1) $(MODULES_$(1)) -- $(or $(PARTS_$(1)),$(1))

headers:
	@$(foreach h,$(HEADERS),$(call gen_header,$(h)) > $(h).h.tmp && mv $(h).h.tmp $(h).h && echo "wrote $(h).h" &&) true

print-headers:
	@echo $(HEADERS)

# The sources clang-format lays out (.clang-format; checked by tests/sh/style.sh)
FORMAT_FILES = $(wildcard src/*/*.h src/*/*.c cli/*.h cli/*.c examples/*.c)
format:
	clang-format -i $(FORMAT_FILES)

print-format-files:
	@echo $(FORMAT_FILES)

# A private copy of header H in folder OUT (for work in progress that must
# not touch the committed headers): make dev-header H=lapped OUT=/tmp/x
dev-header:
	@mkdir -p $(OUT) && $(call gen_header,$(H)) > $(OUT)/$(H).h && echo "wrote $(OUT)/$(H).h"

# Fails when a committed header differs from what `make headers` would write.
check-headers:
	@mkdir -p $(BUILD)/gen; status=0; \
	$(foreach h,$(HEADERS),$(call gen_header,$(h)) > $(BUILD)/gen/$(h).h; \
	  if ! cmp -s $(BUILD)/gen/$(h).h $(h).h; then \
	    echo "$(h).h is stale: run 'make headers' and commit it"; status=1; fi;) \
	exit $$status

# The CLI: one object per source, each header's implementation in its own
# (cli/impl_NAME.c), so that `make -j` compiles the four in parallel.
CLI_OBJ := $(patsubst cli/%.c,$(BUILD)/cli/%.o,$(CLI_SRC))

$(BUILD)/patchwork: $(CLI_OBJ)
	$(CC) $(ALL_CFLAGS) -o $@ $(CLI_OBJ) $(LDLIBS) -pthread

$(BUILD)/cli/impl_%.o: cli/impl_%.c %.h
	@mkdir -p $(BUILD)/cli
	$(CC) $(ALL_CFLAGS) -c -o $@ $<

$(BUILD)/cli/%.o: cli/%.c $(wildcard cli/*.h) $(HEADER_FILES)
	@mkdir -p $(BUILD)/cli
	$(CC) $(ALL_CFLAGS) -c -o $@ $<

$(BUILD)/tests/test_render_portable: tests/test_render.c

$(BUILD)/tests/%: tests/%.c tests/pwtest.h $(COMMON_SRC) $(HEADER_FILES)
	@mkdir -p $(BUILD)/tests
	$(CC) $(ALL_CFLAGS) -o $@ $< $(LDLIBS)

# the renderer's tests and benchmark run its bands on POSIX threads (PW_THREADS), the synthesis benchmarks their tiles
$(BUILD)/tests/test_render $(BUILD)/tests/test_render_portable $(BUILD)/tests/test_threads $(BUILD)/bench/bench_render $(BUILD)/bench/bench_tiled $(BUILD)/bench/bench_pgp_synth $(BUILD)/bench/bench_threads: LDLIBS += -pthread

$(BUILD)/examples/%: examples/%.c $(HEADER_FILES)
	@mkdir -p $(BUILD)/examples
	$(CC) $(ALL_CFLAGS) -o $@ $< $(LDLIBS)

BENCH_CFLAGS := $(WARN) -O2 -g -DNDEBUG -I.

$(BUILD)/bench/%: bench/%.c $(wildcard bench/*.h) $(COMMON_SRC) $(HEADER_FILES)
	@mkdir -p $(BUILD)/bench
	$(CC) $(BENCH_CFLAGS) -o $@ $< $(LDLIBS)

# Peers of the benchmarks (Debian packages, each optional): bench/probe.sh
# decides at build time whether Eigen (libeigen3-dev) and OSMesa
# (libosmesa6-dev) can be built against; without one, the benchmark builds
# without that peer and says so when it runs. Peer code is in bench/ only.
$(BUILD)/bench/bench_sparse: bench/bench_sparse.c bench/peer_eigen.cpp $(wildcard bench/*.h) $(COMMON_SRC)
	@mkdir -p $(BUILD)/bench/obj
	@if sh bench/probe.sh eigen "$(CXX)"; then set -x; \
	  $(CXX) -Wall -Wextra -O2 -g -DNDEBUG $$(sh bench/probe.sh eigen-flags) -c bench/peer_eigen.cpp -o $(BUILD)/bench/obj/peer_eigen.o && \
	  $(CC) $(BENCH_CFLAGS) -DBENCH_EIGEN -c $< -o $(BUILD)/bench/obj/bench_sparse.o && \
	  $(CXX) -o $@ $(BUILD)/bench/obj/bench_sparse.o $(BUILD)/bench/obj/peer_eigen.o $(LDLIBS); \
	else echo "bench_sparse: Eigen (libeigen3-dev) not found: built without its peer"; set -x; \
	  $(CC) $(BENCH_CFLAGS) -o $@ $< $(LDLIBS); fi

OSMESA_BENCH := $(BUILD)/bench/bench_render $(BUILD)/bench/bench_lapped
$(OSMESA_BENCH): $(BUILD)/bench/%: bench/%.c $(wildcard bench/*.h) $(COMMON_SRC) $(HEADER_FILES)
	@mkdir -p $(BUILD)/bench
	@if sh bench/probe.sh osmesa "$(CC)"; then set -x; \
	  $(CC) $(BENCH_CFLAGS) -DBENCH_OSMESA -o $@ $< $(LDLIBS) -lOSMesa; \
	else echo "$*: OSMesa (libosmesa6-dev) not found: built without its peer"; set -x; \
	  $(CC) $(BENCH_CFLAGS) -o $@ $< $(LDLIBS); fi

demo:
	@$(MAKE) --no-print-directory -j$(JOBS) $(BUILD)/patchwork
	./$(BUILD)/patchwork demo out

# (test-build has a recipe so that make says nothing when all is built)
test-build: $(BUILD)/patchwork $(TEST_BIN) $(EX_BIN)
	@:

test:
	@$(MAKE) --no-print-directory -j$(JOBS) test-build
	@SANITIZE=$(SANITIZE) sh tests/run.sh $(BUILD) $(JOBS)

bench: $(BENCH_BIN) $(BENCH_TOOLS) $(BUILD)/patchwork
	@sh bench/run.sh $(BUILD)

bench-report: $(BENCH_BIN) $(BENCH_TOOLS) $(BUILD)/patchwork
	@sh bench/run.sh $(BUILD) bench/results.md

# compile time of each header's implementation; BASE=rev adds that revision's headers
bench-compile: headers
	@bash bench/compile.sh $(BASE)

data: $(BUILD)/patchwork
	@sh tools/make_data.sh $(BUILD)/patchwork

# the versions in tests/js/package-lock.json, exactly
js:
	cd tests/js && npm ci --no-audit --no-fund

FUZZ_DIR := build/fuzz
FUZZ_TARGETS := $(patsubst fuzz/%.c,$(FUZZ_DIR)/%,$(FUZZ_SRC))

$(FUZZ_DIR)/%: fuzz/%.c fuzz/fuzz.h $(HEADER_FILES) $(COMMON_SRC)
	@mkdir -p $(FUZZ_DIR)
	$(FUZZ_CC) -g1 -O1 -I. -fsanitize=fuzzer,address,undefined -fno-sanitize-recover=all -o $@ $< -lm

fuzz-targets: $(FUZZ_TARGETS)
	@:

fuzz-build:
	@$(MAKE) --no-print-directory -j$(JOBS) fuzz-targets

fuzz: fuzz-build
	@sh fuzz/run.sh $(FUZZ_SECONDS) $(JOBS)

# FUZZ_SECONDS from the command line or the environment, else half an hour
FUZZ_LONG_SECONDS := $(if $(filter command line environment,$(origin FUZZ_SECONDS)),$(FUZZ_SECONDS),1800)
fuzz-long: fuzz-build
	@sh fuzz/long.sh $(FUZZ_LONG_SECONDS) $(JOBS) $(FUZZ_ONLY)

clean:
	rm -rf build build-san out
