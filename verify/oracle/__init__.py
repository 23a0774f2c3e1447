"""The reference oracle (``verify oracle``): the golden dataset and its checker
(:mod:`~verify.oracle.reference`), graded verdicts (:mod:`~verify.oracle.grading`), hard cases,
running another implementation (:mod:`~verify.oracle.impl`), which exact model explains it
(:mod:`~verify.oracle.explain`) and the JUnit report (:mod:`~verify.oracle.junit`)."""
