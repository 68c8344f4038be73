"""Book-only code: the prose formats the chapters share (:mod:`gyrolib.book.report`), the
reproduction ledger (:mod:`gyrolib.book.ledger`) and how to cite the book and a ledger item
(:mod:`gyrolib.book.cite`)."""
