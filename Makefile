# AMDO Lab entry points. Each target sets up .venv on first use (and again when
# environment.txt or pyproject.toml change); later runs reuse it.
PYTHON ?= python3
VENV   := .venv
PY     := $(VENV)/bin/python
STAMP  := $(VENV)/.amdo-installed
NBVAL  := --nbval --nbval-sanitize-with tests/nbval_sanitize.cfg
EGL_PACKAGES     := libegl1 libegl-mesa0
BROWSER_PACKAGES := chromium chromium-driver
R_PACKAGES       := r-base-core r-cran-lme4

.PHONY: book site site-student test test-second-kernel lab lab-student figures release grade check-env setup system-packages egl clean

# Execute every chapter, then build the HTML book into build/book/.
book: $(STAMP)
	$(PY) -m amdo_lab build

# The HTML book alone, from the executed notebooks as they are (nothing is executed).
site: $(STAMP)
	$(PY) -m amdo_lab site

# The student book, from the release (no solutions; the download button serves the release notebook).
site-student: $(STAMP)
	$(PY) -m amdo_lab release
	$(PY) -m amdo_lab site --student

# Unit tests, nbval over every notebook, and the book in a headless browser
# (tests/test_browser.py builds the site from the committed notebooks).
test: $(STAMP)
	$(PY) -m pytest tests notebooks $(NBVAL)

# nbval over every notebook again, under a second OpenBLAS kernel (tests/blas_kernels.py picks it:
# Nehalem on x86-64, Haswell where Nehalem is the default): checked outputs must not depend on the CPU.
test-second-kernel: $(STAMP)
	@kernel=$$($(PY) tests/blas_kernels.py); \
	echo "notebooks under OPENBLAS_CORETYPE=$$kernel (this machine: $$($(PY) tests/blas_kernels.py --current))"; \
	OPENBLAS_CORETYPE=$$kernel $(PY) -m pytest notebooks $(NBVAL)

# JupyterLab on the instructor's notebooks. As root (a container's or course VM's default user)
# Jupyter refuses to start without --allow-root: `python -m amdo_lab lab` passes it when the user
# id is 0. LAB_ARGS adds JupyterLab options, e.g. LAB_ARGS="--no-browser --port=8899".
lab: $(STAMP)
	$(PY) -m amdo_lab lab $(LAB_ARGS)

# JupyterLab on the student release (build/release/, written first when missing).
lab-student: $(STAMP)
	$(PY) -m amdo_lab lab --student $(LAB_ARGS)

figures: $(STAMP)
	$(PY) -m amdo_lab figures

# The student release in build/release/ (nbgrader's layout: solutions and hidden tests removed,
# locked cells, gradebook in build/gradebook.db).
release: $(STAMP)
	$(PY) -m amdo_lab release

# Grade a folder of submitted notebooks (flat, or one folder per student) with nbgrader:
# make grade SUBMISSIONS=path/to/folder (grades.csv, feedback/ and the gradebook inside it).
grade: $(STAMP)
	@test -n "$(SUBMISSIONS)" || { echo "usage: make grade SUBMISSIONS=path/to/folder"; exit 2; }
	$(PY) -m amdo_lab grade "$(SUBMISSIONS)"

check-env: $(STAMP)
	$(PY) -m amdo_lab check-env

setup: $(STAMP)

$(STAMP): environment.txt pyproject.toml
	@$(PYTHON) -c 'import sys; sys.exit(sys.version_info < (3, 11))' || \
	  { echo "AMDO Lab needs Python 3.11 or newer: run 'make PYTHON=python3.11 ...'"; exit 1; }
	@test -x $(PY) || $(PYTHON) -m venv $(VENV)
	$(PY) -m pip install --quiet --upgrade pip
	$(PY) -m pip install --quiet -r environment.txt
	@$(MAKE) --no-print-directory system-packages
	@touch $(STAMP)

# System packages, installed with apt-get when missing and we are root; otherwise the command
# is printed and the workbook runs without them:
#   EGL       off-screen 3-D figures (without it they fall back to matplotlib)
#   Chromium  and its driver: the browser test of the book (skipped without them, except in CI)
#   R + lme4  chapter 5's cross-check of our GLMM fit (skipped without them)
system-packages:
	@missing=""; \
	ldconfig -p 2>/dev/null | grep -q 'libEGL\.so\.1' || missing="$$missing $(EGL_PACKAGES)"; \
	{ command -v chromium || command -v chromium-browser; } >/dev/null 2>&1 || missing="$$missing chromium"; \
	command -v chromedriver >/dev/null 2>&1 || missing="$$missing chromium-driver"; \
	Rscript -e 'suppressMessages(library(lme4))' >/dev/null 2>&1 || missing="$$missing $(R_PACKAGES)"; \
	if [ -z "$$missing" ]; then \
	  echo "system packages found: EGL, Chromium and chromedriver, R with lme4"; \
	elif [ "$$(id -u)" = 0 ] && command -v apt-get >/dev/null; then \
	  echo "installing system packages:$$missing"; \
	  apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends $$missing; \
	else \
	  echo "missing system packages:$$missing (3-D figures fall back to matplotlib; the browser"; \
	  echo "and lme4 tests are skipped). To install them run:"; \
	  echo "  sudo apt-get update && sudo apt-get install -y$$missing"; \
	fi

# Kept for the README's troubleshooting: EGL alone.
egl:
	@if ldconfig -p 2>/dev/null | grep -q 'libEGL\.so\.1'; then \
	  echo "EGL found: 3-D figures render off-screen"; \
	elif [ "$$(id -u)" = 0 ] && command -v apt-get >/dev/null; then \
	  echo "installing EGL ($(EGL_PACKAGES)) for off-screen 3-D figures"; \
	  apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq $(EGL_PACKAGES); \
	else \
	  echo "EGL is missing: 3-D figures will fall back to matplotlib. To fix it run:"; \
	  echo "  sudo apt-get update && sudo apt-get install -y $(EGL_PACKAGES)"; \
	fi

clean:
	rm -rf build
