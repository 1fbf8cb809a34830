"""The gallery page shows tables of scores and, per item, the paper figure and the command that
makes it again; images link to themselves at native size."""

from illusio.gallery.html import Item, Section, Table, write_gallery


def test_tables_figures_and_commands_are_on_the_page(tmp_path):
    section = Section(
        "S",
        "text",
        [Item("a.png", "cap", "det", figure="Dehos et al. 2014, Figure 22", command="illusio sis-scene -o a.png")],
        [Table("scores", ["method", "error"], [["baseline", "18 %"], ["loscos <b>", "13 %"]])],
    )
    page = write_gallery(tmp_path, "t", [section]).read_text()
    assert "<table><caption>scores</caption><tr><th>method</th><th>error</th></tr>" in page
    assert "<td>loscos &lt;b&gt;</td><td>13 %</td>" in page  # cells escaped
    assert "(Dehos et al. 2014, Figure 22)" in page and "<code>illusio sis-scene -o a.png</code>" in page
    assert "<a href='a.png'><img src='a.png'" in page  # a click opens it 1:1
