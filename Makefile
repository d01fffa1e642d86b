# Velum: the two commands a user types (see README.md), and a few more.
PRESET ?= release
BUILD  := build/$(PRESET)
JOBS   ?= $(shell nproc)
CMAKE_FLAGS ?= $(if $(CI),-DVELUM_WERROR=ON,)

.PHONY: all deps configure build check demo bench verify asan clean format

all: build

deps:
	@scripts/install-deps

configure: deps
	@cmake --preset $(PRESET) $(CMAKE_FLAGS) > /dev/null

build: configure
	@cmake --build $(BUILD) -j $(JOBS)

check: build
	@cd $(BUILD) && ctest -LE 'verification|slow' -j $(JOBS) --output-on-failure

demo: build
	@tools/run-demo $(BUILD)/velum out

bench: build
	@tools/run-bench $(BUILD) out/bench

verify: build
	@cd $(BUILD) && ctest -L verification -j $(JOBS) --output-on-failure

asan:
	@$(MAKE) check PRESET=asan

format:
	@git ls-files '*.cpp' '*.hpp' | xargs clang-format -i

clean:
	rm -rf build out
