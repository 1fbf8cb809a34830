import pytest

from illusio.core import ShaderError
from illusio.core.programs import preprocess


def write(tmp_path, name, text):
    p = tmp_path / name
    p.parent.mkdir(parents=True, exist_ok=True)
    p.write_text(text)
    return p


def test_include_is_expanded_once_and_defines_overridden(tmp_path):
    write(tmp_path, "lib/helper.glsl", "float helper() { return 2.0; }\n")
    main = write(
        tmp_path,
        "main.glsl",
        '#version 430\n#include "lib/helper.glsl"\n#include "lib/helper.glsl"\n#define GAIN 1.0\n',
    )
    src, files = preprocess(main, {"GAIN": 3.5}, stage="FRAGMENT_SHADER")
    assert src.splitlines()[0] == "#version 430"
    assert src.count("float helper()") == 1
    assert "#define GAIN 3.5" in src and "#define GAIN 1.0" not in src
    assert "#define FRAGMENT_SHADER" in src
    assert [f.name for f in files] == ["main.glsl", "helper.glsl"]


def test_unknown_define_and_missing_include_are_errors(tmp_path):
    main = write(tmp_path, "a.glsl", "#version 430\n#define KNOWN 1\n")
    with pytest.raises(ShaderError, match="no #define for TYPO"):
        preprocess(main, {"TYPO": 2})
    bad = write(tmp_path, "b.glsl", '#version 430\n#include "nope.glsl"\n')
    with pytest.raises(ShaderError, match="nope.glsl"):
        preprocess(bad)
    no_version = write(tmp_path, "c.glsl", "void main() {}\n")
    with pytest.raises(ShaderError, match="#version"):
        preprocess(no_version)


def test_program_cache_compiles_once_per_define_set(ctx, tmp_path):
    p = write(
        tmp_path,
        "fill.glsl",
        '#version 430\n#define VALUE 0.25\n#include "common/fullscreen.glsl"\n'
        "#if defined(FRAGMENT_SHADER)\nout vec4 c;\nvoid main() { c = vec4(VALUE); }\n#endif\n",
    )
    a = ctx.programs.get(p)
    assert ctx.programs.get(p) is a
    b = ctx.programs.get(p, VALUE=0.75)
    assert b is not a


def test_compile_error_names_file_and_line(ctx, tmp_path):
    p = write(
        tmp_path,
        "broken.glsl",
        '#version 430\n#include "common/fullscreen.glsl"\n#if defined(FRAGMENT_SHADER)\n'
        "out vec4 c;\nvoid main() {\n  c = vec4(undefined_name);\n}\n#endif\n",
    )
    with pytest.raises(ShaderError, match=r"broken\.glsl:6"):
        ctx.programs.get(p)
