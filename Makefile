# AMDO Lab entry points. Each target sets up .venv on first use (and again when
# environment.txt or pyproject.toml change); later runs reuse it.
PYTHON ?= python3
VENV   := .venv
PY     := $(VENV)/bin/python
STAMP  := $(VENV)/.amdo-installed
NBVAL  := --nbval --nbval-sanitize-with tests/nbval_sanitize.cfg
EGL_PACKAGES := libegl1 libegl-mesa0

.PHONY: book test lab figures check-env setup egl clean

book: $(STAMP)
	$(PY) -m amdo_lab build

test: $(STAMP)
	$(PY) -m pytest tests notebooks $(NBVAL)

lab: $(STAMP)
	$(VENV)/bin/jupyter lab notebooks/

figures: $(STAMP)
	$(PY) -m amdo_lab figures

check-env: $(STAMP)
	$(PY) -m amdo_lab check-env

setup: $(STAMP)

$(STAMP): environment.txt pyproject.toml
	@$(PYTHON) -c 'import sys; sys.exit(sys.version_info < (3, 11))' || \
	  { echo "AMDO Lab needs Python 3.11 or newer: run 'make PYTHON=python3.11 ...'"; exit 1; }
	@test -x $(PY) || $(PYTHON) -m venv $(VENV)
	$(PY) -m pip install --quiet --upgrade pip
	$(PY) -m pip install --quiet -r environment.txt
	@$(MAKE) --no-print-directory egl
	@touch $(STAMP)

# Off-screen 3-D needs EGL. Install it when missing and we are root; otherwise say how.
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
