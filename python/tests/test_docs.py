"""Every public name of the package has a docstring (numpy conventions)."""

import inspect

import dynapath


def public_members(obj):
    for name, member in inspect.getmembers(obj):
        if not name.startswith("_"):
            yield name, member


def test_every_public_name_is_documented():
    missing = []
    for name in dynapath.__all__:
        obj = getattr(dynapath, name)
        if not (inspect.isclass(obj) or callable(obj)):
            continue
        if not (obj.__doc__ or "").strip():
            missing.append(name)
        if inspect.isclass(obj):
            for member_name, member in public_members(obj):
                if member_name in ("metadata", "render_mode", "dtype"):
                    continue
                if not (getattr(member, "__doc__", None) or "").strip():
                    missing.append(f"{name}.{member_name}")
    assert not missing, f"no docstring: {missing}"
