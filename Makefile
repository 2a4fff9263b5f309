# halfpoint: FPGA motion-control core and toolchain.
#   make setup   create .venv/ with the pinned dependencies (run by the others)
#   make test    lint + model tests + cocotb/Verilator tests (what CI runs)
#   make demo    shipped arcs through the model and the RTL, plot in build/demo/
#   make bench   performance figures, table + build/bench.json
#   make synth   Yosys + nextpnr: area and Fmax table, build/synth/report.json,
#                and the example board tops (build/synth/boards.json, bitstreams)
#   make boards  the example board tops alone
#   make lint    verilator --lint-only -Wall on rtl/
#   make formal  SymbiYosys proofs (all tasks) and mutants, table + build/formal/report.json
#   make mutate  mutation testing (Yosys mutate, MUTANTS per module, seeded), table +
#                build/mutate/report.json; MODULES= limits it (default: every module)
#   make soak    SEGMENTS random arcs and lines (default 10^6, SEED, SOAK_AXES = NA 2..6)
#                through the compiled Verilator harness, checked move by move
#                against the model (JOBS model workers); BATCHES=FIRST:END runs
#                only those batches of 100 (a long soak in parts)
#   make clean   remove build/ (keeps .venv/)

PYTHON  ?= python3
VENV    := .venv
VPY     := $(VENV)/bin/python
STAMP   := $(VENV)/.setup-done
JOBS    ?= 2

.PHONY: setup test lint demo bench synth boards formal mutate soak clean distclean

SEEDS   ?= 3
MUTANTS ?= 200
MODULES ?=
SEGMENTS ?= 1000000
SEED    ?= 1
SOAK_AXES ?= 3

setup: $(STAMP)

$(STAMP): requirements.txt pyproject.toml
	@$(PYTHON) -c 'import sys; sys.exit(0 if sys.version_info >= (3, 10) else "halfpoint needs Python 3.10 or newer")'
	$(PYTHON) -m venv $(VENV)
	$(VPY) -m pip install --quiet --upgrade pip
	$(VPY) -m pip install --quiet -r requirements.txt
	$(VPY) -m pip install --quiet --no-deps --editable .
	@touch $@

lint: setup
	$(VPY) -m halfpoint.flows.lint

test: setup lint
	$(VPY) -m pytest -n $(JOBS) tb

demo: setup
	$(VENV)/bin/halfpoint demo --out build/demo

bench: setup
	$(VPY) -m halfpoint.flows.bench

synth: setup
	$(VPY) -m halfpoint.flows.synth --seeds $(SEEDS) --jobs $(JOBS)

formal: setup
	$(VPY) -m halfpoint.flows.formal --jobs $(JOBS)

mutate: setup
	$(VPY) -m halfpoint.flows.mutate --count $(MUTANTS) --jobs $(JOBS) $(MODULES)

soak: setup
	$(VPY) -m halfpoint.flows.soak --segments $(SEGMENTS) --seed $(SEED) \
		--axes $(SOAK_AXES) --jobs $(JOBS) $(if $(BATCHES),--batches $(BATCHES))

boards: setup
	$(VPY) -m halfpoint.flows.synth --boards-only --jobs $(JOBS)

clean:
	rm -rf build

distclean: clean
	rm -rf $(VENV)
