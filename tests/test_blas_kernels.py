"""The second BLAS kernel the notebooks are run under differs from the one in effect."""

import pytest

from blas_kernels import current_kernel, second_kernel


@pytest.mark.parametrize(("current", "machine", "second"), [
    ("Haswell", "x86_64", "Nehalem"), ("SkylakeX", "x86_64", "Nehalem"), ("Nehalem", "x86_64", "Haswell"),
    ("NEOVERSEN1", "aarch64", "ARMV8"), ("ARMV8", "aarch64", "NEOVERSEN1"),
])
def test_second_kernel_is_another_one(current, machine, second):
    assert second_kernel(current, machine) == second


def test_current_kernel_is_named():
    assert current_kernel()
