"""The lattice kernel template specialised per scene: generated kernels differ only in their
effect flags."""



from craquelure import codegen
from craquelure.lattice.engine import (
    KERNEL_TEMPLATE,
    kernel_flags,
)


def test_generated_kernels_differ_only_in_flags():
    options = dict(periodic_x=False, node_averaged=False, bending=False, parallel=True)
    a, _ = codegen.generate(KERNEL_TEMPLATE, kernel_flags(("beams",), **options))
    b, _ = codegen.generate(KERNEL_TEMPLATE, kernel_flags(("beams", "contact"), **options))
    assert "CONTACT = False" in a and "CONTACT = True" in b
    diff = [(x, y) for x, y in zip(a.splitlines(), b.splitlines(), strict=True) if x != y]
    assert diff == [("CONTACT = False", "CONTACT = True")]
