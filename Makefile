# The project's commands. `make book` and `make test` are the two that matter (see README.md);
# both bootstrap the virtual environment .venv from requirements/lock.txt on first use.
SHELL := /bin/bash
.SHELLFLAGS := -eo pipefail -c
VENV ?= .venv
PY := $(VENV)/bin/python

.PHONY: help venv book book-student test test-slow golden bench lab lock clean

help:
	@echo "make book       build the site (paper profile) into _build/html"
	@echo "make book-student  the student edition (no solutions) into _build/student/_build/html"
	@echo "make test       ruff, pytest, strict nbval, strict site build (fast), browser check"
	@echo "make test-slow  paper-scale checks marked 'slow'"
	@echo "make golden     regenerate tests/golden/*.ipynb from the chapters"
	@echo "make bench      run benchmarks/ and print medians and ratios"
	@echo "make lab        open the chapters as notebooks in JupyterLab"
	@echo "make lock       re-resolve requirements/requirements.in into requirements/lock.txt"
	@echo "make clean      remove _build"

venv:
	@VENV=$(VENV) tools/bootstrap.sh

book: venv
	@$(PY) tools/build_book.py --profile paper

book-student: venv
	@$(PY) tools/build_book.py --profile paper --edition student

test: venv
	@$(PY) tools/run_tests.py

test-slow: venv
	@FUSIONCENTER_PROFILE=paper $(PY) -m pytest -p no:cacheprovider -m slow tests

golden: venv
	@$(PY) tools/make_golden.py

bench: venv
	@$(PY) benchmarks/run.py

lab: venv
	@$(VENV)/bin/jupyter lab --notebook-dir=book

lock:
	@tools/lock.sh

clean:
	rm -rf _build
