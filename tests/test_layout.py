"""The layout the README describes is the layout of the code.

The README's "Layout" section lists geokin's modules from the bottom layer
up; each imports only from those above it in the list, and none reads a
private name of another.
"""

import ast
import pathlib
import re

ROOT = pathlib.Path(__file__).resolve().parents[1]
PACKAGE = ROOT / "geokin"


def layout_order() -> list[str]:
    """Return the README's layout entries in order: module paths and package folders."""
    readme = (ROOT / "README.md").read_text(encoding="utf-8")
    section = readme.split("## Layout", 1)[1].split("```", 2)[1]
    return [entry.rstrip("/")
            for entry in re.findall(r"^geokin/([\w/]+?)(?:\.py)?\s", section, flags=re.M)]


def entry_of(module: str, order: list[str]) -> str:
    """Return the layout entry a module belongs to: itself, or its package."""
    for entry in order:
        if module == entry or module.startswith(entry + "/"):
            return entry
    raise AssertionError(f"geokin/{module}.py is not in the README's layout")


def module_name(path: pathlib.Path) -> str:
    relative = path.relative_to(PACKAGE).with_suffix("")
    parts = relative.parts[:-1] if relative.name == "__init__" else relative.parts
    return "/".join(parts)


def imports(path: pathlib.Path):
    """Yield (target module, imported names, line) for every geokin import of a module."""
    tree = ast.parse(path.read_text(encoding="utf-8"))
    here = module_name(path).split("/")
    package = here if path.name == "__init__.py" else here[:-1]
    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom):
            if node.level:
                base = package[:len(package) - node.level + 1]
                target = [*base, *(node.module.split(".") if node.module else [])]
            elif node.module and node.module.split(".")[0] == "geokin":
                target = node.module.split(".")[1:]
            else:
                continue
            names = [alias.name for alias in node.names]
            if not node.module or (node.level and not target[len(base):]):
                # ``from . import plotting``: each name is a module, or a name of the package
                for name in names:
                    module = "/".join([*target, name])
                    if (PACKAGE / module).is_dir() or (PACKAGE / f"{module}.py").is_file():
                        yield module, [], node.lineno
                    else:
                        yield "/".join(target), [name], node.lineno
            else:
                yield "/".join(target), names, node.lineno
        elif isinstance(node, ast.Import):
            for alias in node.names:
                if alias.name.split(".")[0] == "geokin":
                    yield "/".join(alias.name.split(".")[1:]), [], node.lineno


def sources():
    return sorted(p for p in PACKAGE.rglob("*.py") if p != PACKAGE / "__init__.py")


def test_every_module_is_in_the_readme_layout():
    order = layout_order()
    assert order, "the README has no layout"
    for path in sources():
        entry_of(module_name(path), order)
    for entry in order:
        assert (PACKAGE / entry).is_dir() or (PACKAGE / f"{entry}.py").is_file(), entry


def test_each_module_imports_only_from_those_above_it():
    order = layout_order()
    wrong = []
    for path in sources():
        mine = entry_of(module_name(path), order)
        for target, _, line in imports(path):
            if not target:
                continue
            theirs = entry_of(target, order)
            if theirs != mine and order.index(theirs) > order.index(mine):
                wrong.append(f"geokin/{module_name(path)}:{line} imports {target}")
    assert not wrong, "\n".join(wrong)


def test_no_module_imports_a_private_name_of_another():
    wrong = []
    for path in sources():
        for target, names, line in imports(path):
            for name in names:
                if name.startswith("_") and not name.startswith("__"):
                    wrong.append(f"geokin/{module_name(path)}:{line} imports {target}.{name}")
    assert not wrong, "\n".join(wrong)


def test_no_module_reads_a_private_attribute_of_another():
    """``from . import primitives as prim`` then ``prim._patch`` is reading a private name."""
    wrong = []
    for path in sources():
        tree = ast.parse(path.read_text(encoding="utf-8"))
        modules = {alias.asname or alias.name
                   for node in ast.walk(tree) if isinstance(node, ast.ImportFrom)
                   and (node.level or (node.module or "").startswith("geokin"))
                   and not node.module for alias in node.names}
        modules |= {alias.asname or alias.name for node in ast.walk(tree)
                    if isinstance(node, ast.ImportFrom) and node.level and node.module is None
                    for alias in node.names}
        for node in ast.walk(tree):
            if (isinstance(node, ast.Attribute) and isinstance(node.value, ast.Name)
                    and node.value.id in modules and node.attr.startswith("_")
                    and not node.attr.startswith("__")):
                wrong.append(f"geokin/{module_name(path)}:{node.lineno} reads "
                             f"{node.value.id}.{node.attr}")
    assert not wrong, "\n".join(wrong)
