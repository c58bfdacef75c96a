# The two commands of the README. Both install what is missing, then build.
#   make demo   run the default swarm (Shao 2020 50x50) with the ground station
#               and its web console (the URL is printed; DEMO_HTTP=port)
#   make test   run the whole test suite (unit + integration)
#   make test-quick  the unit and bus tests only (a few minutes with the build):
#               the loop to run while changing code
#   make test-core-only  configure, build and run a PHEROMESH_CORE_ONLY=ON tree
#               ($(BUILD)-core-only) with both DDS vendors and npm hidden:
#               sim, validate, experiment, sweep work; the rest is refused
#   make fuzz  build the libFuzzer harnesses (clang, build-fuzz/) and run each
#               for FUZZ_SECONDS (default 60) on its corpus (docs/fuzzing.md)
#   make package  build the Debian packages pheromesh_<version>_<arch>.deb and
#               pheromesh-dev_... into $(BUILD)/ (docs/install.md)
BUILD ?= build
JOBS ?= $(shell nproc)
DEMO_SCENARIO ?= scenarios/shao2020-50x50.textproto
DEMO_TICKS ?= 600
DEMO_OUT ?= out/demo
DEMO_HTTP ?= 8080
SCALE_MAX ?= 400
FUZZ_SECONDS ?= 60
UNITY ?= ON

.PHONY: all deps build demo test test-quick test-core-only package bench bench-scale soak fuzz clean

all: build

deps:
	./scripts/install-deps.sh

# A unity build (about eight sources per compiler run) by default: a cold
# build of the tree takes about half the time, which is most of what a fresh
# clone's `make test` spends before its first test (docs/contributing.md,
# "Build time"). UNITY=OFF configures a tree file by file, for a loop that
# changes one source at a time. Either applies when $(BUILD) is configured.
$(BUILD)/CMakeCache.txt:
	cmake -S . -B $(BUILD) -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_UNITY_BUILD=$(UNITY)

build: deps $(BUILD)/CMakeCache.txt
	cmake --build $(BUILD) -j$(JOBS)

demo: build
	$(BUILD)/bin/pheromesh run $(DEMO_SCENARIO) --ticks $(DEMO_TICKS) --out $(DEMO_OUT) --http $(DEMO_HTTP)

test: build
	cd $(BUILD) && ctest --output-on-failure -j2 --timeout 900

test-quick: build
	cd $(BUILD) && ctest --output-on-failure -j2 --timeout 300 -L 'unit|bus'

test-core-only: deps
	bash tests/core_only/core_only_build.sh $(CURDIR) $(CURDIR)/$(BUILD)-core-only

package: build
	cd $(BUILD) && cpack -G DEB

bench: build
	$(BUILD)/bin/pheromesh_bench_layers
	$(BUILD)/bin/pheromesh_bench_views
	$(BUILD)/bin/pheromesh-bench-latency
	bench/console_bench.sh $(BUILD)
	bench/console_limits.sh $(BUILD)

# Swarms of 25 UAVs up to SCALE_MAX, one process each: what a size costs
# (out/bench-scale/scale.md). Keep the host otherwise idle.
bench-scale: build
	$(BUILD)/bin/pheromesh bench scale scenarios/scale-100x100.textproto --max $(SCALE_MAX)

# Each harness in turn, one process (the fuzz tree is separate from $(BUILD)).
fuzz: deps
	./fuzz/fuzz.sh --seconds $(FUZZ_SECONDS)

# One swarm of SOAK_PROCESSES processes for SOAK_DURATION with a fault every
# minute: RSS, file descriptors and threads per role over time, and their
# growth per hour (out/bench-soak/soak.md). In cells: a flat swarm of 200
# processes does not discover on one host (docs/dds.md). Keep the host
# otherwise idle.
SOAK_PROCESSES ?= 200
SOAK_DURATION ?= 1h
soak: build
	$(BUILD)/bin/pheromesh bench soak scenarios/scale-100x100.textproto --processes $(SOAK_PROCESSES) \
	    --duration $(SOAK_DURATION) --fault-every 60s --sample-every 10s --extra "--dds-profile cells"

clean:
	rm -rf $(BUILD) build-fuzz out
