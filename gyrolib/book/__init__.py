"""Book-only code: the prose formats the chapters share (:mod:`gyrolib.book.report`) and the
reproduction ledger (:mod:`gyrolib.book.ledger`)."""
