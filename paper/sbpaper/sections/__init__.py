"""One module per section of the paper; each has generate(ctx), which quotes into ctx.book,
writes its tables and says whether its suite was measured."""
