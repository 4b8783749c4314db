"""Runs one pytest file for ctest; exits 77 (ctest: skipped) when numpy or pytest is missing."""
import sys

try:
    import numpy  # noqa: F401
    import pytest
except ImportError as e:
    print(f"SKIP: {e} (install python3-numpy and python3-pytest, scripts/install-deps.sh)")
    sys.exit(77)

sys.exit(pytest.main(["-q", "-p", "no:cacheprovider", "-rs", *sys.argv[1:]]))
