"""Whatever the input, the compiler answers with diagnostics, never a crash."""

from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from inmoov_dsl import compile_source
from inmoov_dsl.errors import GestError
from inmoov_dsl.parse import parse

WORDS = ["peace", "g", "index", "middle", "fingers", "all", "fist", "pose", "group", "use",
         "wait", "hold", "repeat", "over", "stagger", ":", ",", "90", "180", "200", "-3",
         "0.5", "1s", "300ms", "2 s", "x", '"peace.gest"', "#c", "\n", "\n    ", "\n        ",
         "\t", "@"]

FUZZ = settings(max_examples=300, deadline=None, suppress_health_check=[HealthCheck.too_slow])


@FUZZ
@given(st.text(max_size=200))
def test_any_text_parses_or_is_a_diagnostic(text):
    try:
        parse(text, "fuzz.gest")
    except GestError as exc:
        (diagnostic,) = exc.diagnostics
        assert diagnostic.pos.file == "fuzz.gest" and diagnostic.pos.line >= 1
        assert exc.format().startswith("fuzz.gest:")


@FUZZ
@given(st.lists(st.sampled_from(WORDS), max_size=40).map(" ".join))
def test_any_token_soup_compiles_or_is_a_diagnostic(text):
    source = "g:\n    " + text
    try:
        compile_source(source, gesture="g", file="soup.gest")
    except GestError as exc:
        assert all(d.severity == "error" for d in exc.diagnostics)
        assert exc.format()
