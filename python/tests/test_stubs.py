"""The hand-written type stubs (clustersurf/__init__.pyi, _clustersurf.pyi) against the live module,
and the bound functions' docstrings: a binding added or changed without its stub fails here."""

import ast
import inspect
import pathlib
import re

import pytest

import clustersurf
import clustersurf._clustersurf as native

PACKAGE = pathlib.Path(clustersurf.__file__).parent
# The option schema's stages whose keywords a binding taking **kwargs has spelled out in its stub.
SCHEMA_STAGES = {"reconstruct": {"build"}, "Tree.mesh": {"mesh"}, "Tree.render": {"render"}}
# Members every pybind11 class has, or that pickling adds; not part of the typed interface.
IGNORED_MEMBERS = {"__init__", "__new__", "__module__", "__doc__", "__dict__", "__weakref__", "__getstate__",
                   "__setstate__", "__repr__", "__hash__", "__eq__"}


def parse_stub(name: str) -> ast.Module:
    path = PACKAGE / name
    assert path.exists(), f"{path} is not installed with the package (python/CMakeLists.txt)"
    return ast.parse(path.read_text(), filename=str(path))


def top_level_names(module: ast.Module) -> dict:
    """Name -> node of what a stub defines or imports at its top level."""
    names = {}
    for node in module.body:
        if isinstance(node, (ast.FunctionDef, ast.ClassDef)):
            names[node.name] = node
        elif isinstance(node, ast.ImportFrom):
            for alias in node.names:
                names[alias.asname or alias.name] = node
        elif isinstance(node, ast.AnnAssign) and isinstance(node.target, ast.Name):
            names[node.target.id] = node
        elif isinstance(node, ast.Assign):
            for target in node.targets:
                if isinstance(target, ast.Name):
                    names[target.id] = node
    return names


def parameters(function: ast.FunctionDef) -> list:
    """[(name, kind, default)] of a def; kind "positional" or "keyword" (after *); the default is
    the literal value or the marker "<required>"."""
    args = function.args
    out = []
    positional = args.posonlyargs + args.args
    defaults = [None] * (len(positional) - len(args.defaults)) + list(args.defaults)
    for arg, default in zip(positional, defaults):
        out.append((arg.arg, "positional", "<required>" if default is None else ast.literal_eval(default)))
    if args.vararg:
        out.append(("*" + args.vararg.arg, "varargs", "<required>"))
    for arg, default in zip(args.kwonlyargs, args.kw_defaults):
        out.append((arg.arg, "keyword", "<required>" if default is None else ast.literal_eval(default)))
    if args.kwarg:
        out.append(("**" + args.kwarg.arg, "varkw", "<required>"))
    return out


def live_parameters(function) -> list:
    """The same list for a live function: from pybind11's signature line (the docstring's first
    line), which names every keyword and shows every default, or from inspect for Python code."""
    if inspect.isfunction(function):
        out = []
        kinds = {inspect.Parameter.POSITIONAL_ONLY: "positional", inspect.Parameter.POSITIONAL_OR_KEYWORD: "positional",
                 inspect.Parameter.KEYWORD_ONLY: "keyword"}
        for p in inspect.signature(function).parameters.values():
            default = "<required>" if p.default is inspect.Parameter.empty else p.default
            out.append((p.name, kinds[p.kind], default))
        return out
    signature = (function.__doc__ or "").splitlines()[0]
    assert re.match(r"^\w+\(.*\) -> ", signature), f"no pybind11 signature line in {function!r}: {signature!r}"
    assert "Overloaded function" not in function.__doc__, f"{function!r} is overloaded: stub it with @overload"
    return parameters(ast.parse(f"def {signature}: ...").body[0])


def stubbed_functions(stub: ast.Module):
    """(qualified name, def node, live object) of every function and method the stub defines."""
    for node in stub.body:
        if isinstance(node, ast.FunctionDef):
            yield node.name, node, getattr(native, node.name, None)
        elif isinstance(node, ast.ClassDef):
            cls = getattr(native, node.name, None)
            for member in node.body:
                if isinstance(member, ast.FunctionDef):
                    decorators = {d.id for d in member.decorator_list if isinstance(d, ast.Name)}
                    if "property" not in decorators:
                        yield f"{node.name}.{member.name}", member, getattr(cls, member.name, None)


def public_names(module) -> set:
    return {name for name in vars(module) if not name.startswith("_") or name == "__version__"} - {
        name for name, value in vars(module).items() if inspect.ismodule(value)}


def test_package_stub_names_everything_public():
    stub = parse_stub("__init__.pyi")
    names = top_level_names(stub)
    missing = sorted(public_names(clustersurf) - set(names))
    assert not missing, f"public names of clustersurf missing from __init__.pyi: {missing}"
    extra = sorted(n for n in names if not n.startswith("_") and not hasattr(clustersurf, n))
    assert not extra, f"__init__.pyi names what clustersurf lacks: {extra}"
    stub_all = next(ast.literal_eval(n.value) for n in stub.body
                    if isinstance(n, ast.Assign) and any(getattr(t, "id", None) == "__all__" for t in n.targets))
    assert stub_all == clustersurf.__all__
    # Each re-export comes from the module that really defines it.
    for node in stub.body:
        if isinstance(node, ast.ImportFrom) and node.level == 1:
            source = __import__(f"clustersurf.{node.module}", fromlist=["_"])
            for alias in node.names:
                assert getattr(source, alias.name) is getattr(clustersurf, alias.asname or alias.name), alias.name
    assert (PACKAGE / "py.typed").exists()


def test_extension_stub_names_everything_public():
    names = top_level_names(parse_stub("_clustersurf.pyi"))
    missing = sorted(public_names(native) - set(names))
    assert not missing, f"bindings missing from _clustersurf.pyi: {missing}"
    extra = sorted(n for n in names if not n.startswith("_") and not hasattr(native, n) and
                   not isinstance(names[n], ast.ImportFrom) and n not in ("np",))
    assert not extra, f"_clustersurf.pyi names what the module lacks: {extra}"


def test_stub_classes_have_every_member_and_base():
    stub = parse_stub("_clustersurf.pyi")
    for node in stub.body:
        if not isinstance(node, ast.ClassDef):
            continue
        cls = getattr(native, node.name)
        assert [ast.unparse(b) for b in node.bases] == [b.__name__ for b in cls.__bases__ if b is not object] or (
            not node.bases and cls.__bases__[0].__name__ == "pybind11_object"), node.name
        stubbed = {m.name for m in node.body if isinstance(m, ast.FunctionDef)}
        if issubclass(cls, BaseException):
            continue
        live = {name for name in vars(cls) if name not in IGNORED_MEMBERS}
        assert not sorted(live - stubbed), f"{node.name} members missing from the stub: {sorted(live - stubbed)}"
        assert not sorted(stubbed - live), f"{node.name} stub members the class lacks: {sorted(stubbed - live)}"
        for member in node.body:
            if isinstance(member, ast.FunctionDef):
                decorators = {d.id for d in member.decorator_list if isinstance(d, ast.Name)}
                kind = type(inspect.getattr_static(cls, member.name)).__name__
                if "property" in decorators:
                    assert kind == "property", f"{node.name}.{member.name} is not a property"
                elif "staticmethod" in decorators:
                    assert kind == "staticmethod", f"{node.name}.{member.name} is not a staticmethod"
                else:
                    assert kind == "instancemethod", f"{node.name}.{member.name} is a {kind}"


@pytest.mark.parametrize("qualified, node, live", [pytest.param(*f, id=f[0]) for f in
                                                   stubbed_functions(parse_stub("_clustersurf.pyi"))])
def test_stub_signature_matches_the_binding(qualified, node, live):
    assert live is not None, f"{qualified} is stubbed but not bound"
    expected = live_parameters(live)
    if expected and expected[0][0] == "self":  # pybind11 writes self with its type
        expected[0] = ("self", "positional", "<required>")
    stubbed = parameters(node)
    if expected and expected[-1][1] == "varkw" and stubbed[-1][1] != "varkw":
        # The binding takes the option schema's keywords as **kwargs: the stub names each one,
        # with the schema's default, in the schema's order, before the binding's own keywords.
        stages = SCHEMA_STAGES[qualified]
        schema = [(o["name"], "keyword", o["default"]) for o in native.option_schema() if o["stage"] in stages]
        own = [p for p in stubbed if p[0] not in {name for name, _, _ in schema}]
        assert own == expected[:-1], qualified
        assert [p for p in stubbed if p not in own] == schema, qualified
        return
    assert stubbed == expected, qualified


def test_python_functions_of_the_package_are_typed():
    for function in (clustersurf.from_open3d, clustersurf.Mesh.to_open3d, clustersurf.PointCloud.to_open3d):
        signature = inspect.signature(function)
        assert signature.return_annotation is not inspect.Signature.empty, function
        for p in signature.parameters.values():
            assert p.name == "self" or p.annotation is not inspect.Parameter.empty, (function, p.name)


def bound_callables():
    for name, value in sorted(vars(native).items()):
        if name.startswith("_") or isinstance(value, type):
            continue
        if callable(value):
            yield name, value
    for cls in (native.Tree, native.Node, native.TiledRun):
        for name, value in sorted(vars(cls).items()):
            if name in IGNORED_MEMBERS or isinstance(value, property):
                continue
            yield f"{cls.__name__}.{name}", getattr(cls, name)


@pytest.mark.parametrize("qualified, function", [pytest.param(*f, id=f[0]) for f in bound_callables()])
def test_docstring_describes_every_argument(qualified, function):
    lines = function.__doc__.splitlines()
    body = "\n".join(lines[1:]).strip()
    assert body, f"{qualified} has no description under its signature"
    assert len(body.splitlines()[0]) > 10, f"{qualified}: the description's first line is not a sentence"
    for name, _, _ in live_parameters(function):
        if name != "self" and not name.startswith("*"):  # **kwargs: the options, described by name elsewhere
            assert re.search(rf"\b{name}\b", body), f"{qualified}'s docstring does not describe {name!r}"


def test_properties_have_docstrings():
    for cls in (native.Tree, native.Node, native.TiledRun):
        for name, value in vars(cls).items():
            if isinstance(value, property):
                assert (value.__doc__ or "").strip(), f"{cls.__name__}.{name} has no docstring"
                assert not value.__doc__.startswith("\n"), f"{cls.__name__}.{name}: docstring starts with a blank line"
