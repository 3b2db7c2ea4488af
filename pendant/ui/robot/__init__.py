"""The Robot tab (tool, base, tool shape, safety), and the IO and Simulator tabs beside it."""
