# The README's two commands are `make demo` and `make test`; both install what is missing first.
PYTHON ?= python3
# Re-install only when a source or build file changed since the last install.
SOURCES := $(shell find cpp python cmake -type f -not -path '*/__pycache__/*' 2>/dev/null) CMakeLists.txt pyproject.toml scripts/bootstrap.sh
STAMP := build/.installed-$(subst /,_,$(PYTHON))
BENCH_STAMP := build/.installed-bench-$(subst /,_,$(PYTHON))

.PHONY: setup demo test typecheck bench bench-quick wheel sdist test-wheel clean
setup: $(STAMP)

$(STAMP): $(SOURCES)
	bash scripts/bootstrap.sh "$(PYTHON)" test,viz
	@mkdir -p build && touch $@

demo: setup
	$(PYTHON) -m meshsmith demo --out demo-output

test: setup
	$(PYTHON) -m pytest -q tests

# The package's type annotations, checked against the installed numpy/scipy stubs (mypy is in the test extra).
typecheck: setup
	$(PYTHON) -m mypy python/meshsmith

# Peers are installed only here (Open3D is large); `make bench CHAPTERS="io topology"` runs a subset.
# The bench install includes the test and viz extras, so it stands for `setup` too.
$(BENCH_STAMP): $(SOURCES)
	bash scripts/bootstrap.sh "$(PYTHON)" test,viz,bench
	@mkdir -p build && touch $(STAMP) $@

bench: $(BENCH_STAMP)
	$(PYTHON) benchmarks/run_all.py $(CHAPTERS)

# A manylinux wheel in dist/ with the Debian libraries it links copied in (auditwheel), built in
# the same build directory as setup; `make test-wheel` installs it into a fresh venv under /tmp
# and runs the whole suite against that install.
wheel:
	bash scripts/build_wheel.sh "$(PYTHON)"

test-wheel: wheel
	bash scripts/test_wheel.sh "$(PYTHON)"

# dist/meshsmith-<version>.tar.gz, its contents checked; `make sdist SDIST_BUILD=--build` also
# builds a wheel from it (cold, in a temporary directory).
sdist:
	bash scripts/build_sdist.sh "$(PYTHON)" $(SDIST_BUILD)

# Every chapter on small inputs (a few minutes): a Markdown table of medians and ratios on stdout,
# benchmarks/results/quick.json; exits non-zero when a benchmark crashes or a result check fails.
bench-quick: $(BENCH_STAMP)
	$(PYTHON) benchmarks/run_all.py --quick $(CHAPTERS)

clean:
	rm -rf build demo-output dist
