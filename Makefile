# Two entry points that work on a fresh machine: `make demo` and `make test`.
# One .venv, two installs: `make demo` installs only what running mlc needs (`pip install -e .`,
# RUN_STAMP); `make test` adds the test extras (pytest, hypothesis, dask, cython ...: TEST_STAMP).
PY ?= python3
VENV := .venv
BIN := $(VENV)/bin
RUN_STAMP := $(VENV)/.installed-run
TEST_STAMP := $(VENV)/.installed-test

.PHONY: test demo bench lint fuzz clean

$(BIN)/python:
	$(PY) -m venv $(VENV)
	$(BIN)/pip install --quiet --upgrade pip

$(RUN_STAMP): pyproject.toml | $(BIN)/python
	$(BIN)/pip install --quiet -e .
	touch $(RUN_STAMP)

# the test install holds all that running needs too: the run stamp is renewed with it
$(TEST_STAMP): pyproject.toml | $(BIN)/python
	$(BIN)/pip install --quiet -e '.[test]'
	touch $(TEST_STAMP) $(RUN_STAMP)

test: $(TEST_STAMP)
	$(BIN)/pytest

# the fuzz targets of the suite with a larger budget and fresh randomness (the suite runs
# them derandomized in CI); FUZZ_EXAMPLES per target; the edge-operand walk of every
# instruction form then takes every edge and random combinations of them
FUZZ_EXAMPLES ?= 2000
fuzz: $(TEST_STAMP)
	env -u CI MLC_FUZZ_EXAMPLES=$(FUZZ_EXAMPLES) $(BIN)/pytest -q tests/test_fuzz_inputs.py tests/test_checked_means_runs.py

lint: $(TEST_STAMP)
	$(BIN)/ruff check mlctool tests bench

demo: $(RUN_STAMP)
	mkdir -p out
	$(BIN)/mlc check samples/nc5/*.il
	$(BIN)/mlc build samples/nc5/conveyor.il -o out/conveyor.mlx --listing out/conveyor.lst
	$(BIN)/mlc objdump out/conveyor.mlx
	$(BIN)/mlc sim out/conveyor.mlx --stimulus samples/nc5/conveyor.stim --vcd out/conveyor.vcd
	@echo "waveform written to out/conveyor.vcd (open with: gtkwave out/conveyor.vcd out/conveyor.gtkw)"
	cd samples/project && ../../$(BIN)/mlc build && ../../$(BIN)/mlc test --coverage --coverage-dir ../../out --junit ../../out/project-junit.xml
	@echo "project built into samples/project/build/; test and coverage reports in out/"
	$(BIN)/mlc test samples/nc5-mill --junit $(CURDIR)/out/mill-junit.xml
	@echo "the mill ran against the virtual NC (docs/nc5.md \"Worked examples\"); next, its scenario that fails on purpose:"
	$(BIN)/mlc test samples/nc5-mill/broken --out $(CURDIR)/out/mill-broken; test $$? -eq 1
	@echo "failed as it should (exit 1): waveform and report in out/mill-broken/"

# the benchmarks run in their own venv: the simulator's peers (awlsim, pyrung) are not test
# dependencies, and pyrung's pyclickplc pins an older pymodbus than mlctool needs; mlctool
# goes in with its cluster extra (bench/batch_speed.py's Dask LocalCluster figures), its
# native extra (Cython: bench/sim_speed.py's native engine row), its opcua extra
# (asyncua: bench/commission_speed.py's OPC UA row) and its verify extra (z3:
# bench/verify_speed.py's symbolic engine, against pyrung's prover). bench/lsp_memory.py is left out: it
# takes about 15 minutes (docs/bench.md)
BENCH_VENV := .venv-bench
BENCH_BIN := $(BENCH_VENV)/bin
BENCH_STAMP := $(BENCH_VENV)/.installed

$(BENCH_STAMP): pyproject.toml
	$(PY) -m venv $(BENCH_VENV)
	$(BENCH_BIN)/pip install --quiet --upgrade pip
	$(BENCH_BIN)/pip install --quiet awlsim pyrung
	$(BENCH_BIN)/pip install --quiet -e '.[cluster,native,opcua,verify]'
	touch $(BENCH_STAMP)

bench: $(BENCH_STAMP)
	$(BENCH_BIN)/python bench/startup.py
	$(BENCH_BIN)/python bench/check_speed.py
	$(BENCH_BIN)/python bench/build_speed.py
	$(BENCH_BIN)/python bench/sim_speed.py
	$(BENCH_BIN)/python bench/batch_speed.py
	$(BENCH_BIN)/python bench/start_memory.py
	$(BENCH_BIN)/python bench/nc5_speed.py
	$(BENCH_BIN)/python bench/debug_speed.py
	$(BENCH_BIN)/python bench/lsp_speed.py
	$(BENCH_BIN)/python bench/server_speed.py
	$(BENCH_BIN)/python bench/commission_speed.py
	$(BENCH_BIN)/python bench/verify_speed.py

clean:
	rm -rf $(VENV) $(BENCH_VENV) out .pytest_cache
