# Two entry points that work on a fresh machine: `make demo` and `make test`.
PY ?= python3
VENV := .venv
BIN := $(VENV)/bin
STAMP := $(VENV)/.installed

.PHONY: test demo bench lint fuzz clean

$(STAMP): pyproject.toml
	$(PY) -m venv $(VENV)
	$(BIN)/pip install --quiet --upgrade pip
	$(BIN)/pip install --quiet -e '.[test]'
	touch $(STAMP)

test: $(STAMP)
	$(BIN)/pytest

# the fuzz targets of the suite with a larger budget and fresh randomness (the suite runs
# them derandomized in CI); FUZZ_EXAMPLES per target; the edge-operand walk of every
# instruction form then takes every edge and random combinations of them
FUZZ_EXAMPLES ?= 2000
fuzz: $(STAMP)
	env -u CI MLC_FUZZ_EXAMPLES=$(FUZZ_EXAMPLES) $(BIN)/pytest -q tests/test_fuzz_inputs.py tests/test_checked_means_runs.py

lint: $(STAMP)
	$(BIN)/ruff check mlctool tests bench

demo: $(STAMP)
	mkdir -p out
	$(BIN)/mlc check samples/nc5/*.il
	$(BIN)/mlc build samples/nc5/conveyor.il -o out/conveyor.mlx --listing out/conveyor.lst
	$(BIN)/mlc objdump out/conveyor.mlx
	$(BIN)/mlc sim out/conveyor.mlx --stimulus samples/nc5/conveyor.stim --vcd out/conveyor.vcd
	@echo "waveform written to out/conveyor.vcd (open with: gtkwave out/conveyor.vcd out/conveyor.gtkw)"
	cd samples/project && ../../$(BIN)/mlc build && ../../$(BIN)/mlc test --coverage --coverage-dir ../../out --junit ../../out/project-junit.xml
	@echo "project built into samples/project/build/; test and coverage reports in out/"

# the benchmarks run in their own venv: the simulator's peers (awlsim, pyrung) are not test
# dependencies, and pyrung's pyclickplc pins an older pymodbus than mlctool needs; mlctool
# goes in with its cluster extra (bench/batch_speed.py's Dask LocalCluster figures) and its
# native extra (Cython: bench/sim_speed.py's native engine row)
BENCH_VENV := .venv-bench
BENCH_BIN := $(BENCH_VENV)/bin
BENCH_STAMP := $(BENCH_VENV)/.installed

$(BENCH_STAMP): pyproject.toml
	$(PY) -m venv $(BENCH_VENV)
	$(BENCH_BIN)/pip install --quiet --upgrade pip
	$(BENCH_BIN)/pip install --quiet awlsim pyrung
	$(BENCH_BIN)/pip install --quiet -e '.[cluster,native]'
	touch $(BENCH_STAMP)

bench: $(BENCH_STAMP)
	$(BENCH_BIN)/python bench/startup.py
	$(BENCH_BIN)/python bench/check_speed.py
	$(BENCH_BIN)/python bench/build_speed.py
	$(BENCH_BIN)/python bench/sim_speed.py
	$(BENCH_BIN)/python bench/batch_speed.py
	$(BENCH_BIN)/python bench/start_memory.py

clean:
	rm -rf $(VENV) $(BENCH_VENV) out .pytest_cache
