from multicrank.cli import main

main()
