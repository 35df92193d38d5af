# Two entry points that work on a fresh machine: `make demo` and `make test`.
PY ?= python3
VENV := .venv
BIN := $(VENV)/bin
STAMP := $(VENV)/.installed

.PHONY: test demo bench lint clean

$(STAMP): pyproject.toml
	$(PY) -m venv $(VENV)
	$(BIN)/pip install --quiet --upgrade pip
	$(BIN)/pip install --quiet -e '.[test]'
	touch $(STAMP)

test: $(STAMP)
	$(BIN)/pytest

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

bench: $(STAMP)
	$(BIN)/python bench/check_speed.py
	$(BIN)/python bench/build_speed.py
	# the simulator's peers, for bench/sim_speed.py only (not test dependencies)
	$(BIN)/pip install --quiet awlsim pyrung
	$(BIN)/python bench/sim_speed.py

clean:
	rm -rf $(VENV) out .pytest_cache
