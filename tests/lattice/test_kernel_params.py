"""Parameters declared once: the kernel's index constants and the engine's packing by name
agree for every one of the template's parameters."""

import ast
import inspect

from craquelure.lattice import kernel_template
from craquelure.lattice.engine import default_params


def _index_constants(module):
    """{constant: parameter name} for every ``NAME = _index("name")`` in the module."""
    found = {}
    for node in ast.parse(inspect.getsource(module)).body:
        if not isinstance(node, ast.Assign):
            continue
        targets = node.targets[0]
        names = targets.elts if isinstance(targets, ast.Tuple) else [targets]
        values = node.value.elts if isinstance(node.value, ast.Tuple) else [node.value]
        for target, value in zip(names, values, strict=False):
            if (isinstance(value, ast.Call) and isinstance(value.func, ast.Name)
                    and value.func.id == "_index"):
                found[target.id] = value.args[0].value
    return found


def test_every_parameter_has_one_index_and_packing_puts_it_there():
    consts = _index_constants(kernel_template)
    names = kernel_template.PARAMS
    assert kernel_template.N_PARAMS == len(names) == 39
    assert sorted(consts.values()) == sorted(names)  # each parameter exactly once
    values = {name: 0.5 + i for i, name in enumerate(names)}
    p = default_params(**values)
    for const, name in consts.items():
        assert p[getattr(kernel_template, const)] == values[name], (const, name)
