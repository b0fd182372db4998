"""`wec-cosim bench`: the report that answers "which settings should I use, how fast, how wrong, and where does it
break" (issue 19).

Stages, one module each: :mod:`.cases` (what runs: scenarios, overrides, factors), :mod:`.points` (run one
variant, time it, score it), :mod:`.errors` (error measures against independent answers), then the parts of the
report (:mod:`.work_precision`, :mod:`.hard_cases`, :mod:`.scaling`, :mod:`.anchors`) and :mod:`.report` (Markdown,
PNG figures and CSV of every point).
"""
