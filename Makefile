# Every target does all the set-up it needs: dependencies, configure, build.
BUILD      ?= build
SAN_BUILD  ?= build-sanitize
BENCH_BUILD ?= build-release
JOBS       ?= $(shell nproc)

.PHONY: all deps build python test sanitize sweep demo bench format clean

all: build

deps:
	@bash scripts/install-deps.sh

# CI and development builds treat warnings as errors; a user's plain `cmake` does not.
# Line tables only (-g1): stack traces and profiles keep file:line, and the build takes a third
# less time than with full debug information (CI's budget).
DEV_FLAGS := -DCGAMESH_WERROR=ON -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O2 -g1 -DNDEBUG" -DCMAKE_CXX_FLAGS_DEBUG="-g1"

build: deps
	cmake -S . -B $(BUILD) -DCMAKE_BUILD_TYPE=RelWithDebInfo $(DEV_FLAGS)
	cmake --build $(BUILD) -j $(JOBS)

# The Python module (python/): the extension and the package cgamesh in $(BUILD)/python.
python: deps
	cmake -S . -B $(BUILD) -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCGAMESH_BUILD_PYTHON=ON
	cmake --build $(BUILD) -j $(JOBS) --target _cgamesh
	@echo "cgamesh: built $(abspath $(BUILD))/python/cgamesh; use it with"
	@echo "  PYTHONPATH=$(abspath $(BUILD))/python /usr/bin/python3 -c 'import cgamesh'"
	@echo "or install it into a venv: python3 -m venv --system-site-packages .venv && .venv/bin/pip install --no-build-isolation ."

test: build
	ctest --test-dir $(BUILD) --output-on-failure -j $(JOBS)

# The same tests under AddressSanitizer + UndefinedBehaviorSanitizer.
sanitize: deps
	cmake -S . -B $(SAN_BUILD) -DCMAKE_BUILD_TYPE=Debug -DCGAMESH_SANITIZE=ON -DCGAMESH_BUILD_BENCH=OFF $(DEV_FLAGS)
	cmake --build $(SAN_BUILD) -j $(JOBS)
	ctest --test-dir $(SAN_BUILD) --output-on-failure -j $(JOBS)

demo: build
	bash scripts/demo.sh $(BUILD)/apps/cli/cgamesh

# Every field model (../shared/data, Debian's assimp-testmodels) through every command: a report
# and pictures in $(BUILD)/sweep. Slow; not part of `test`. SWEEP_ARGS adds options (--filter, --jobs...).
sweep: build
	python3 scripts/field_sweep.py --cli $(BUILD)/apps/cli/cgamesh --out $(BUILD)/sweep $(SWEEP_ARGS)

bench: deps
	cmake -S . -B $(BENCH_BUILD) -DCMAKE_BUILD_TYPE=Release -DCGAMESH_BUILD_PYTHON=ON
	cmake --build $(BENCH_BUILD) -j $(JOBS) --target cgamesh_bench _cgamesh
	$(BENCH_BUILD)/bench/cgamesh_bench --benchmark_min_time=0.2 --benchmark_repetitions=5 --benchmark_report_aggregates_only=true --benchmark_out=$(BENCH_BUILD)/bench.json --benchmark_out_format=json
	python3 scripts/bench_table.py $(BENCH_BUILD)/bench.json
	PYTHONPATH=$(BENCH_BUILD)/python /usr/bin/python3 python/bench/skin_bench.py $(BENCH_BUILD)/bench/cgamesh_bench

format:
	find include src apps tests bench -name '*.hpp' -o -name '*.cpp' | xargs clang-format -i

clean:
	rm -rf $(BUILD) $(SAN_BUILD) $(BENCH_BUILD)
