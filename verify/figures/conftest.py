"""pytest on verify/: test_figures_key.py is a script (ctest figures.key passes it the dampsym
binary and a work directory and it runs as it is imported), so pytest does not collect it."""
from typing import List

collect_ignore: List[str] = ["test_figures_key.py"]
