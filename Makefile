# Velum: the two commands a user types (see README.md), and a few more.
PRESET ?= release
BUILD  := build/$(PRESET)
JOBS   ?= $(shell nproc)
CMAKE_FLAGS ?= $(if $(CI),-DVELUM_WERROR=ON,)

.PHONY: all deps configure build check demo bench profile-c9 compare-fenicsx verify asan fuzz clean format install

all: build

deps:
	@scripts/install-deps

# Configured once (configuring again at every `make` was a visible part of `make demo`): the
# build re-runs CMake itself when a CMakeLists.txt changes; flags given on the command line
# configure again.
configure: deps
	@if [ ! -f $(BUILD)/build.ninja ] || [ -n "$(CMAKE_FLAGS)" ]; then \
	  cmake --preset $(PRESET) $(CMAKE_FLAGS) > /dev/null; fi

build: configure
	@cmake --build $(BUILD) -j $(JOBS)

check: build
	@cd $(BUILD) && ctest -LE 'verification|slow' -j $(JOBS) --output-on-failure

# The velum command and the Python module (into Debian's dist-packages for the prefix:
# /usr/local/lib/python3.X/dist-packages by default); PREFIX=/usr or DESTDIR=... as usual.
install: build
	@cmake --install $(BUILD) $(if $(PREFIX),--prefix $(PREFIX),)

demo: build
	@tools/run-demo $(BUILD)/velum out

bench: build
	@scripts/install-deps --bench
	@tools/run-bench $(BUILD) out/bench $(FILTER)

# The main job's CPU per Newton iteration by stage (perf; three runs of the C9 isotropic canopy).
profile-c9: build
	@scripts/install-deps --profile
	@bench/c9-profile --velum $(BUILD)/velum

# Velum against FEniCSx on the Hencky membrane (bench/compare-fenicsx; minutes of CPU).
compare-fenicsx: build
	@scripts/install-deps --bench
	@bench/compare-fenicsx --velum $(BUILD)/velum

# Cases A and B through CTest (their log becomes the report's B section), then the paper's
# membrane-versus-network experiments C1, C2 at every size (tools/network-verification), which
# write docs/verification.md and its plots in docs/verification/.
verify: build
	@mkdir -p out
	@cd $(BUILD) && ctest -L verification -LE network -j $(JOBS) --output-on-failure \
		> $(CURDIR)/out/ctest-verification.log 2>&1; status=$$?; \
		cat $(CURDIR)/out/ctest-verification.log; cd $(CURDIR) && \
		tools/network-verification --velum $(BUILD)/velum --full --out out/network-verification \
			--ctest-log out/ctest-verification.log --report docs/verification.md \
			--notes tests/network/verification-notes.md \
		&& exit $$status

asan:
	@$(MAKE) check PRESET=asan

# libFuzzer (clang, ASan + UBSan; preset fuzz) on the model, Gmsh and .inp readers, each for
# FUZZ_SECONDS (default 60), seeded from the examples and the test meshes; crashes, leaks and
# slow inputs land in out/fuzz/<harness>/ (tools/run-fuzz). FUZZ_RUNS=1000000 stops each at
# that many executions instead (FUZZ_SECONDS=0: no time limit). Not part of `make check`.
FUZZ_SECONDS ?= 60
FUZZ_RUNS ?= -1
fuzz:
	@scripts/install-deps --fuzz
	@cmake --preset fuzz > /dev/null
	@cmake --build build/fuzz -j $(JOBS)
	@tools/run-fuzz build/fuzz out/fuzz $(FUZZ_SECONDS) $(FUZZ_RUNS)

format:
	@git ls-files '*.cpp' '*.hpp' | xargs clang-format -i

clean:
	rm -rf build out
