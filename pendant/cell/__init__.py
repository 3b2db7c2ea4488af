"""The robot cell as the pendant sees it: obstacles and tool shape, their forms, geometry and file."""
