# The project's commands. `make book` and `make test` are the two that matter (see README.md);
# both bootstrap the virtual environment .venv from requirements/lock.txt on first use.
SHELL := /bin/bash
.SHELLFLAGS := -eo pipefail -c
VENV ?= .venv
PY := $(VENV)/bin/python

.PHONY: help venv book book-student test test-pythons test-student golden bench lab pdf lock clean

help:
	@echo "make book       build the site (paper profile) into _build/html"
	@echo "make book-student  the student edition (no solutions) into _build/student/_build/html"
	@echo "make test       ruff, pytest, strict nbval, strict site build (fast), browser check, PDF"
	@echo "                WITH=\"pythons student\" (what CI runs): also the library's tests on"
	@echo "                Python 3.12 and the student's path (downloaded chapters, fresh venv)"
	@echo "make golden     regenerate tests/golden/*.ipynb from the chapters"
	@echo "make bench      run benchmarks/ and print medians and ratios"
	@echo "make lab        open the chapters as notebooks in JupyterLab (.md opens as a notebook)"
	@echo "make pdf        the book as PDFs -> _build/pdf/book.pdf, api.pdf, chapters/ (builds the site if missing)"
	@echo "make test-pythons  every library test (the heavy ones too) on Python 3.12 and 3.13 (pyenv)"
	@echo "make test-student  downloaded notebooks run offline in a fresh Python 3.12 (needs the fast build)"
	@echo "make lock       re-resolve requirements/requirements.in into requirements/lock.txt"
	@echo "make clean      remove _build"

venv:
	@VENV=$(VENV) tools/bootstrap.sh

book: venv
	@$(PY) tools/build_book.py --profile paper

book-student: venv
	@$(PY) tools/build_book.py --profile paper --edition student

# WITH="pythons student": also the library's tests on Python 3.12 and the student's path, in
# the same schedule (what CI runs: .ci/run, the GitHub workflow)
WITH ?=
test: venv
	@$(PY) tools/run_tests.py $(if $(strip $(WITH)),--with "$(WITH)")

golden: venv
	@$(PY) tools/make_golden.py

bench: venv
	@$(PY) benchmarks/run.py

# bootstrap (venv) writes binder/overrides.json into the venv's JupyterLab settings: jupytext
# opens the .md chapters as notebooks on a double-click
lab: venv
	@$(VENV)/bin/jupyter lab --notebook-dir=book

# Chromium prints the pages (Debian's package, as for the browser check in `make test`)
pdf: venv
	@command -v chromium-headless-shell >/dev/null 2>&1 || { echo "make pdf: installing Debian's chromium" >&2; \
	  apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq chromium \
	  chromium-headless-shell >/dev/null; }
	@test -f _build/html/index.html || $(PY) tools/build_book.py --profile paper
	@$(PY) tools/pdf_book.py --site _build/html --out _build/pdf/book.pdf

test-pythons: venv
	@$(PY) tools/test_pythons.py

test-student: venv
	@test -f _build/fast/_build/html/index.html || $(PY) tools/build_book.py --profile fast --strict
	@$(PY) tools/student_path.py --site _build/fast/_build/html

lock:
	@tools/lock.sh

clean:
	rm -rf _build
