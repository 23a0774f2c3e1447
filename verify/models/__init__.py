"""The paper's models: Newton's cradle (Sect. 4.1), the disk in a corner (Sect. 4.2), the paper's
own termination and the wedge. Built on the laws (:mod:`verify.laws`) and what is below them."""
