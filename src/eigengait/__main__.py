from eigengait.cli import main

main()
