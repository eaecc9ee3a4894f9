"""The README's example labelled "book 9.9.1" evaluates the book's radar and prints the book's
detection ranges, as the README says it does.

Brooker 9.9.1 (L-band 2-D surveillance radar: 1 m² Swerling 2, Pd 0.9, Pfa 1e-10, 5 MW, 36 dB,
10 pulses) finds 352.8 km in free space from SNR = 230.1 − 40 log10 R = 8.2 dB, and with
0.003 dB/km of one-way atmospheric loss the root of 230.1 − 40 log10 R − 2·0.003·R/km = 8.2
(316 km; about 320 km read off its graph). The book rounds each term of its budget to 0.1 dB
and the noise power by 0.11 dB: 0.15 dB in the SNR constant is 0.87 % in range (R⁻⁴), so 1 %.
"""

import math
import re

from scipy.optimize import brentq

from helpers.paths import REPO

BLOCKS = re.findall(r"```python\n(.*?)```", (REPO / "README.md").read_text(), flags=re.S)
KM = re.compile(r"^(\d+(?:\.\d+)?) km$")


def _example():
    found = [b for b in BLOCKS if "book 9.9.1" in b]
    assert len(found) == 1, "one README example is labelled 'book 9.9.1'"
    return found[0]


def _book_root(alpha_db_km):
    return brentq(lambda r: 230.1 - 40 * math.log10(r) - 2 * alpha_db_km * r / 1e3 - 8.2, 1e3, 1e7)


def test_book_root_is_the_books_free_space_range():
    assert abs(_book_root(0.0) / 352.8e3 - 1) < 1e-3


def test_book_9_9_1_example_prints_the_books_ranges(capsys):
    code = _example()
    exec(compile(code, "README.md example (book 9.9.1)", "exec"), {})
    printed = [float(m.group(1)) * 1e3 for line in capsys.readouterr().out.splitlines() if (m := KM.match(line))]
    assert len(printed) == 2, printed
    free, gas = printed
    assert abs(free / 352.8e3 - 1) < 0.01
    assert abs(gas / _book_root(0.003) - 1) < 0.01
    # the numbers the example's comments announce are the ones it prints
    announced = [float(x) * 1e3 for x in re.findall(r"#[^\n]*?: (\d+\.\d) km \(book", code)]
    assert announced == printed
